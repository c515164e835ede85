//! The shared library's soname carries the ABI version (`ES_ABI_VERSION` in `src/lib.rs`), so a
//! host linked against one ABI never loads another.

fn main() {
    let abi = std::fs::read_to_string("src/lib.rs")
        .expect("src/lib.rs")
        .lines()
        .find_map(|line| line.strip_prefix("pub const ES_ABI_VERSION: u32 = "))
        .and_then(|rest| rest.trim_end_matches(';').trim().parse::<u32>().ok())
        .expect("src/lib.rs declares `pub const ES_ABI_VERSION: u32 = N;`");
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libellipsoid_splat.so.{abi}");
    }
    println!("cargo:rerun-if-changed=src/lib.rs");
}

//! The committed C header is what cbindgen makes of the sources today: a change of the ABI
//! that is not in `include/ellipsoid_splat.h` fails here. `UPDATE_HEADER=1` rewrites it.

use std::path::Path;

#[test]
fn the_committed_header_is_fresh() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml")).unwrap();
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen reads the crate")
        .write(&mut generated);
    let generated = String::from_utf8(generated).unwrap();
    let path = crate_dir.join("include/ellipsoid_splat.h");
    if std::env::var_os("UPDATE_HEADER").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        generated.contains("es_renderer_record_prepass") && generated.contains("ES_ABI_VERSION"),
        "the generated header lacks the API:\n{generated}"
    );
    assert!(
        committed == generated,
        "crates/capi/include/ellipsoid_splat.h is stale: run \
         `UPDATE_HEADER=1 cargo test -p ellipsoid-splat-capi --test header` and commit it"
    );
}

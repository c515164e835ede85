//! Compiles every shader in `glsl/` to SPIR-V in `OUT_DIR` with glslangValidator. Where that
//! compiler is missing, and on docs.rs (`DOCS_RS`), it copies the committed builds from
//! `spirv/` instead (`scripts/update-spirv.sh` refreshes them; a test checks they are
//! byte-identical to what the compiler makes).
//!
//! Writes only to `OUT_DIR`: the SPIR-V, `spirv-files.txt` (this feature set's builds, one a
//! line) and `spirv-origin.txt` (`compiled` and the compiler's version, or `committed` and
//! why). Reruns when a shader or an include changes.
//!
//! `GLSLANG_VALIDATOR` overrides the compiler's path; every build runs with `--spirv-val` and
//! `-I glsl/include`, the includes tracked for rebuilds. Copying the committed builds says so in
//! a warning, and a missing committed file is an error naming it and how to install glslang.
//! `tests/committed_spirv.rs` fails when a committed file differs by a byte from what the
//! installed compiler (`spirv/COMPILER` names the version that made them) makes, or has no
//! source left.

use std::path::{Path, PathBuf};
use std::process::Command;

const STAGES: &[&str] = &["vert", "frag", "comp"];

/// Where the committed SPIR-V lives, relative to the package.
const COMMITTED: &str = "spirv";

/// One SPIR-V file to make: its source, its name in `OUT_DIR` and `spirv/`, the defines and
/// the target environment.
struct Build {
    source: PathBuf,
    spv: String,
    defines: Vec<&'static str>,
    target_env: &'static str,
}

fn main() {
    let glsl = PathBuf::from("glsl");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let tool = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    println!("cargo:rerun-if-env-changed=GLSLANG_VALIDATOR");
    println!("cargo:rerun-if-env-changed=DOCS_RS");
    println!("cargo:rerun-if-changed=glsl");

    // The benchmark's baselines (glsl/research/) and the counting builds are compiled only
    // with the `research` feature: hosts never draw them.
    let research = std::env::var_os("CARGO_FEATURE_RESEARCH").is_some();
    // The offscreen renderer's own shaders (glsl/offscreen/) only with `offscreen`.
    let offscreen = std::env::var_os("CARGO_FEATURE_OFFSCREEN").is_some();
    let builds = builds(&glsl, research, offscreen);

    // docs.rs builds without network or compilers beyond Rust's.
    let origin = if std::env::var_os("DOCS_RS").is_some() {
        copy_committed(&builds, &out, &tool, "DOCS_RS is set")
    } else {
        match compiler_version(&tool) {
            Some(version) => {
                compile(&builds, &glsl, &out, &tool);
                format!("compiled\n{version}\n")
            }
            None => copy_committed(&builds, &out, &tool, "not found"),
        }
    };
    let files: String = builds.iter().map(|b| format!("{}\n", b.spv)).collect();
    write(&out.join("spirv-files.txt"), files.as_bytes());
    write(
        &out.join("spirv-sources.txt"),
        sources_hash(&glsl).as_bytes(),
    );
    write(&out.join("spirv-origin.txt"), origin.as_bytes());
}

/// Every SPIR-V file this feature set needs, in source order.
fn builds(glsl: &Path, research: bool, offscreen: bool) -> Vec<Build> {
    let mut sources = Vec::new();
    collect(glsl, &mut sources);
    sources.retain(|src| research || !src.starts_with(glsl.join("research")));
    sources.retain(|src| offscreen || !src.starts_with(glsl.join("offscreen")));
    sources.sort();
    let mut builds = Vec::new();
    for src in sources {
        println!("cargo:rerun-if-changed={}", src.display());
        let ext = src.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !STAGES.contains(&ext) {
            continue; // includes are tracked above, compiled through their users
        }
        let name = src.file_name().expect("file has a name").to_string_lossy();
        // Compute shaders target SPIR-V 1.6 (Vulkan 1.3), whose LocalSizeId replaces the
        // WorkgroupSize built-in that 1.6 deprecates (a best-practices warning).
        let target_env = if ext == "comp" {
            "vulkan1.3"
        } else {
            "vulkan1.2"
        };
        // Fragment shaders are built with and without AUX_OUTPUTS (they then declare and write
        // the normal and ID attachments: a pass without them must not see those outputs), and
        // for research also with COUNT_FRAGMENTS (they count shaded pixels with an atomic for
        // `bench`; it needs fragmentStoresAndAtomics).
        let mut variants: Vec<(String, Vec<&'static str>)> = vec![(format!("{name}.spv"), vec![])];
        if ext == "frag" {
            variants.push((format!("{name}.aux.spv"), vec!["-DAUX_OUTPUTS"]));
            if research {
                variants.push((format!("{name}.counted.spv"), vec!["-DCOUNT_FRAGMENTS"]));
                variants.push((
                    format!("{name}.aux.counted.spv"),
                    vec!["-DAUX_OUTPUTS", "-DCOUNT_FRAGMENTS"],
                ));
            }
        }
        for (spv, defines) in variants {
            builds.push(Build {
                source: src.clone(),
                spv,
                defines,
                target_env,
            });
        }
    }
    builds
}

/// The compiler's version line, or `None` where `tool` does not exist.
fn compiler_version(tool: &str) -> Option<String> {
    match Command::new(tool).arg("--version").output() {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => panic!("cannot run `{tool}`: {e}"),
        Ok(o) => {
            let stdout = String::from_utf8_lossy(&o.stdout);
            Some(
                stdout
                    .lines()
                    .next()
                    .unwrap_or("unknown version")
                    .to_owned(),
            )
        }
    }
}

/// Compiles every build into `out`; panics with every compile error.
fn compile(builds: &[Build], glsl: &Path, out: &Path, tool: &str) {
    let mut failures = Vec::new();
    for build in builds {
        let result = Command::new(tool)
            .args(["-V", "--target-env", build.target_env, "--spirv-val"])
            .arg(format!("-I{}", glsl.join("include").display()))
            .args(&build.defines)
            .arg("-o")
            .arg(out.join(&build.spv))
            .arg(&build.source)
            .output();
        match result {
            Err(e) => panic!("cannot run `{tool}`: {e}"),
            Ok(o) if !o.status.success() => {
                // glslangValidator prints compile errors on stdout.
                failures.push(format!(
                    "{}:\n{}{}",
                    build.source.display(),
                    String::from_utf8_lossy(&o.stdout),
                    String::from_utf8_lossy(&o.stderr)
                ));
            }
            Ok(_) => {}
        }
    }
    if !failures.is_empty() {
        panic!("\n\nshader compilation failed:\n{}", failures.join("\n"));
    }
}

/// Copies every build's committed SPIR-V into `out`, says so, and returns the origin record.
/// Panics naming the first missing file.
fn copy_committed(builds: &[Build], out: &Path, tool: &str, why: &str) -> String {
    println!("cargo:rerun-if-changed={COMMITTED}");
    let reason = if why == "not found" {
        format!("the shader compiler `{tool}` was not found")
    } else {
        why.to_owned()
    };
    // The committed SPIR-V is only good for the sources it was made from: shaders edited
    // since would silently run stale.
    let recorded =
        std::fs::read_to_string(Path::new(COMMITTED).join("SOURCES")).unwrap_or_default();
    let current = sources_hash(Path::new("glsl"));
    if recorded.trim() != current.trim() {
        panic!(
            "\n\n{reason}, and the committed SPIR-V in {COMMITTED}/ was made from other shader \
             sources than glsl/ holds now (sources {}, recorded {}).\n\
             Install the shader compiler with:  sudo apt-get install glslang-tools\n\
             (then scripts/update-spirv.sh refreshes {COMMITTED}/).\n",
            current.trim(),
            if recorded.is_empty() {
                "none"
            } else {
                recorded.trim()
            }
        );
    }
    println!(
        "cargo:warning={reason}: using the committed SPIR-V in {COMMITTED}/ \
         (install glslang-tools to compile the shaders from glsl/)"
    );
    for build in builds {
        let committed = Path::new(COMMITTED).join(&build.spv);
        if let Err(e) = std::fs::copy(&committed, out.join(&build.spv)) {
            panic!(
                "\n\n{reason}, and the committed SPIR-V `{}` cannot be read ({e}).\n\
                 Install the shader compiler with:  sudo apt-get install glslang-tools\n\
                 or point GLSLANG_VALIDATOR at a glslangValidator binary; in a checkout, \
                 scripts/update-spirv.sh refreshes {COMMITTED}/.\n",
                committed.display()
            );
        }
    }
    format!("committed\n{reason}\n")
}

/// A 64-bit FNV-1a hash of every file under `glsl` (relative path and contents, in path
/// order), as 16 hex digits and a newline: what `spirv/SOURCES` records of the sources the
/// committed SPIR-V was made from.
fn sources_hash(glsl: &Path) -> String {
    let mut files = Vec::new();
    collect(glsl, &mut files);
    files.sort();
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut feed = |bytes: &[u8]| {
        for &b in bytes {
            hash = (hash ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for file in files {
        let relative = file.strip_prefix(glsl).unwrap_or(&file);
        let name: Vec<String> = relative
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        feed(name.join("/").as_bytes());
        feed(&[0]);
        let contents =
            std::fs::read(&file).unwrap_or_else(|e| panic!("cannot read {}: {e}", file.display()));
        feed(&contents);
        feed(&[0]);
    }
    format!("{hash:016x}\n")
}

fn write(path: &Path, bytes: &[u8]) {
    std::fs::write(path, bytes).unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries =
        std::fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            collect(&path, out);
        } else {
            out.push(path);
        }
    }
}

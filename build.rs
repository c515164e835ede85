//! Compiles every shader in `glsl/` to SPIR-V in `OUT_DIR` with glslangValidator.
//! Writes only to `OUT_DIR`; reruns when a shader or an include changes.

use std::path::{Path, PathBuf};
use std::process::Command;

const STAGES: &[&str] = &["vert", "frag", "comp"];

fn main() {
    let glsl = PathBuf::from("glsl");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let tool = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    println!("cargo:rerun-if-env-changed=GLSLANG_VALIDATOR");
    println!("cargo:rerun-if-changed=glsl");

    // The benchmark's baselines (glsl/research/) and the counting builds are compiled only
    // with the `research` feature: hosts never draw them.
    let research = std::env::var_os("CARGO_FEATURE_RESEARCH").is_some();
    let mut sources = Vec::new();
    collect(&glsl, &mut sources);
    sources.retain(|src| research || !src.starts_with(glsl.join("research")));
    sources.sort();
    let mut failures = Vec::new();
    for src in &sources {
        println!("cargo:rerun-if-changed={}", src.display());
        let ext = src.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !STAGES.contains(&ext) {
            continue; // includes are tracked above, compiled through their users
        }
        let name = src.file_name().expect("file has a name").to_string_lossy();
        // Fragment shaders are built with and without AUX_OUTPUTS (they then declare and write
        // the normal and ID attachments: a pass without them must not see those outputs), and
        // for research also with COUNT_FRAGMENTS (they count shaded pixels with an atomic for
        // `bench`; it needs fragmentStoresAndAtomics).
        let mut builds: Vec<(String, Vec<&str>)> = vec![(format!("{name}.spv"), vec![])];
        if ext == "frag" {
            builds.push((format!("{name}.aux.spv"), vec!["-DAUX_OUTPUTS"]));
            if research {
                builds.push((format!("{name}.counted.spv"), vec!["-DCOUNT_FRAGMENTS"]));
                builds.push((
                    format!("{name}.aux.counted.spv"),
                    vec!["-DAUX_OUTPUTS", "-DCOUNT_FRAGMENTS"],
                ));
            }
        }
        for (spv, defines) in builds {
            let mut command = Command::new(&tool);
            // Compute shaders target SPIR-V 1.6 (Vulkan 1.3), whose LocalSizeId replaces the
            // WorkgroupSize built-in that 1.6 deprecates (a best-practices warning).
            let env = if ext == "comp" {
                "vulkan1.3"
            } else {
                "vulkan1.2"
            };
            command
                .args(["-V", "--target-env", env, "--spirv-val"])
                .arg(format!("-I{}", glsl.join("include").display()));
            command.args(&defines);
            let result = command.arg("-o").arg(out.join(&spv)).arg(src).output();
            match result {
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                    panic!(
                        "\n\nshader compiler `{tool}` not found.\n\
                         Install it with:  sudo apt-get install glslang-tools\n\
                         or point GLSLANG_VALIDATOR at a glslangValidator binary.\n"
                    );
                }
                Err(e) => panic!("cannot run `{tool}`: {e}"),
                Ok(o) if !o.status.success() => {
                    // glslangValidator prints compile errors on stdout.
                    failures.push(format!(
                        "{}:\n{}{}",
                        src.display(),
                        String::from_utf8_lossy(&o.stdout),
                        String::from_utf8_lossy(&o.stderr)
                    ));
                }
                Ok(_) => {}
            }
        }
    }
    if !failures.is_empty() {
        panic!("\n\nshader compilation failed:\n{}", failures.join("\n"));
    }
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

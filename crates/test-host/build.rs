//! Compiles the host's mesh shaders (`glsl/`) to SPIR-V in `OUT_DIR` with glslangValidator.

use std::path::PathBuf;
use std::process::Command;

fn main() {
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let tool = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    println!("cargo:rerun-if-env-changed=GLSLANG_VALIDATOR");
    for name in ["host_mesh.vert", "host_mesh.frag"] {
        let src = PathBuf::from("glsl").join(name);
        println!("cargo:rerun-if-changed={}", src.display());
        let output = Command::new(&tool)
            .args(["-V", "--target-env", "vulkan1.2", "--spirv-val", "-o"])
            .arg(out.join(format!("{name}.spv")))
            .arg(&src)
            .output()
            .unwrap_or_else(|e| panic!("cannot run `{tool}` (apt-get install glslang-tools): {e}"));
        // glslangValidator prints compile errors on stdout.
        assert!(
            output.status.success(),
            "{}:\n{}{}",
            src.display(),
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

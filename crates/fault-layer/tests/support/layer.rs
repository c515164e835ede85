//! The fault layer as a test process drives it: installed for the process (a manifest naming
//! the built library, `VK_ADD_LAYER_PATH`, `VK_INSTANCE_LAYERS`), loaded by the test itself so
//! its state lives across instances, and armed through its exported functions.

use std::ffi::{c_char, CStr};
use std::path::PathBuf;
use std::sync::OnceLock;

/// The layer's name in its manifest.
pub const LAYER_NAME: &str = "VK_LAYER_ELLIPSOID_SPLAT_fault_injection";

/// The layer's kinds of fault (`es_fault_arm`'s `kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LayerFault {
    /// `VK_ERROR_OUT_OF_DEVICE_MEMORY` from one call.
    OutOfMemory = 1,
    /// `VK_ERROR_DEVICE_LOST` from one call on.
    DeviceLost = 2,
}

/// The loaded layer library and its control functions.
pub struct FaultLayer {
    arm: unsafe extern "C" fn(u32, u64) -> i32,
    count: unsafe extern "C" fn() -> u64,
    fired: unsafe extern "C" fn() -> *const c_char,
    pause: unsafe extern "C" fn(u32),
    /// Keeps the library loaded (the loader's own handle goes with each instance).
    _library: libloading::Library,
}

/// The built layer library: beside the test executable in `target/<profile>/deps`, where
/// `cargo test` builds it with this crate.
pub fn library_path() -> PathBuf {
    let exe = std::env::current_exe().expect("the test executable's path");
    let deps = exe.parent().expect("target/<profile>/deps");
    let path = deps.join("libes_fault_layer.so");
    assert!(
        path.exists(),
        "{} is missing: `cargo test -p ellipsoid-splat-fault-layer` builds it",
        path.display()
    );
    path
}

/// The layer of this process, installed by the first call: make it before any Vulkan
/// instance exists, with no other thread running (it sets environment variables).
pub fn layer() -> &'static FaultLayer {
    static LAYER: OnceLock<FaultLayer> = OnceLock::new();
    LAYER.get_or_init(FaultLayer::install)
}

impl FaultLayer {
    /// Installs the layer for every Vulkan instance this process creates from now on, and
    /// loads it.
    fn install() -> FaultLayer {
        let library = library_path();
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("fault-layer-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("manifest directory");
        let manifest = format!(
            r#"{{
  "file_format_version": "1.1.2",
  "layer": {{
    "name": "{LAYER_NAME}",
    "type": "GLOBAL",
    "library_path": "{}",
    "api_version": "1.3.239",
    "implementation_version": "1",
    "description": "ellipsoid-splat's test-only fault injection"
  }}
}}
"#,
            library.display()
        );
        std::fs::write(dir.join("fault_layer.json"), manifest).expect("layer manifest");
        let join = |var: &str, first: String| match std::env::var(var) {
            Ok(rest) if !rest.is_empty() => format!("{first}:{rest}"),
            _ => first,
        };
        let layers = join("VK_INSTANCE_LAYERS", LAYER_NAME.to_string());
        let path = join("VK_ADD_LAYER_PATH", dir.display().to_string());
        // Before any instance and thread (the caller's contract): the loader reads them at
        // instance creation.
        std::env::set_var("VK_INSTANCE_LAYERS", layers);
        std::env::set_var("VK_ADD_LAYER_PATH", path);
        // SAFETY: the layer library runs no initialisation code of its own; it is the file the
        // manifest names, so the loader's later dlopen finds this copy and its state.
        let lib = unsafe { libloading::Library::new(&library) }.expect("load the fault layer");
        // SAFETY: the exported functions of `control.rs`, with these signatures.
        unsafe {
            FaultLayer {
                arm: *lib.get(b"es_fault_arm\0").expect("es_fault_arm"),
                count: *lib.get(b"es_fault_count\0").expect("es_fault_count"),
                fired: *lib.get(b"es_fault_fired\0").expect("es_fault_fired"),
                pause: *lib.get(b"es_fault_pause\0").expect("es_fault_pause"),
                _library: lib,
            }
        }
    }

    /// Counts the calls `fault` can hit from now on; the `at`-th (1-based; 0: none) gets it.
    pub fn arm(&self, fault: LayerFault, at: u64) {
        // SAFETY: a plain call into the layer.
        assert_eq!(unsafe { (self.arm)(fault as u32, at) }, 0);
    }

    /// The calls counted since `arm`.
    pub fn count(&self) -> u64 {
        // SAFETY: a plain call into the layer.
        unsafe { (self.count)() }
    }

    /// The call the fault hit, once it has.
    pub fn fired(&self) -> Option<String> {
        // SAFETY: the layer returns null or a static NUL-terminated name.
        let name = unsafe { (self.fired)() };
        (!name.is_null()).then(|| {
            // SAFETY: as above.
            unsafe { CStr::from_ptr(name) }
                .to_string_lossy()
                .into_owned()
        })
    }

    /// Runs `work` with counting and faults paused: the test host's own set-up and
    /// teardown, which are not what a walk looks into.
    pub fn paused<T>(&self, work: impl FnOnce() -> T) -> T {
        // SAFETY: plain calls into the layer.
        unsafe { (self.pause)(1) };
        let result = work();
        // SAFETY: as above.
        unsafe { (self.pause)(0) };
        result
    }
}

//! What the fault walks share: the layer as a test drives it, the host allocator's faults,
//! the faults a walk injects, the test host the embedded runs draw in, the library's log, the
//! run's scenes, and the walk itself.

// Each test binary uses the part its API needs.
#![allow(dead_code)]

pub mod allocator;
pub mod fault;
pub mod host_side;
pub mod layer;
pub mod log;
pub mod scenes;
pub mod walk;

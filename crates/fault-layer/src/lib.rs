//! A Vulkan layer for tests only, never a dependency of the library: it makes the N-th
//! Vulkan call of a run run out of device memory (`VK_ERROR_OUT_OF_DEVICE_MEMORY` from that
//! call alone) or lose the device (`VK_ERROR_DEVICE_LOST` from that call on, wherever the
//! spec lets a call report it), so that one test can walk N over every call of a typical
//! host's run. Being a layer, it reaches the Rust API, the C ABI and the Python package alike
//! without rebuilding any of them.
//!
//! The tests install it with a manifest naming this library (`VK_LAYER_PATH`), enable it with
//! `VK_INSTANCE_LAYERS`, and drive it from the same process through the exported functions
//! of `control.rs` (`es_fault_arm`, `es_fault_count`, `es_fault_fired`, `es_fault_pause`),
//! having loaded this library themselves so that its state outlives every instance. Enabled
//! that way the loader puts it above the validation layer, which sees only what reaches the
//! driver. The parts:
//!
//! - `interface.rs`: the loader-layer interface (negotiation, `GetProcAddr`s, instance and
//!   device creation passing the chain on);
//! - `dispatch.rs`: the next layer's entry points per instance and device;
//! - `intercepts.rs`: the device calls it intercepts, by class;
//! - `control.rs`: the count, the armed fault and what each class of call does under it.
//!
//! # Files
//!
//! | what | where |
//! |---|---|
//! | the fault layer (`docs/testing.md`): loader-layer interface, next layer's entry points, the intercepted calls by class, the count and the armed fault | `src/interface.rs`, `dispatch.rs`, `intercepts.rs`, `control.rs` |
//! | the fault walks: the run's checks, the layer and allocator faults as a test drives them, the test host's side, the runs per API | `tests/support/` (`walk.rs`, `layer.rs`, `allocator.rs`, `fault.rs`, `host_side.rs`, `log.rs`, `scenes.rs`), `tests/offscreen_faults.rs`, `embedded_faults.rs`, `c_abi_faults.rs`; Python's `crates/python/tests/test_faults.py` |

mod control;
mod dispatch;
mod intercepts;
mod interface;

pub use control::{es_fault_arm, es_fault_count, es_fault_fired, es_fault_pause};
pub use interface::{vkNegotiateLoaderLayerInterfaceVersion, NegotiateLayerInterface};

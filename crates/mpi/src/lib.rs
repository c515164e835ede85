//! Sort-last rendering over MPI: each process of a communicator draws its own share of the
//! glyphs with a common camera, and the frames are combined pixel by pixel at a root process
//! into exactly the frame one process drawing every glyph reads back -- colour, view depth,
//! normal and (global) glyph index, bit for bit where the renderer's paths agree bit for bit
//! (lavapipe; see the design document's compositing section for other drivers).
//!
//! Exact because every pixel's winner is decided by one number, the key of
//! [`pixels::key`]: the depth attachment's value (what the renderer's own depth test
//! compares; [`ellipsoid_splat::Frame::device_depth`]) above the glyph's global index, so the
//! nearer glyph wins and of equal depths the lower index, as in one process; and because
//! each process uploads its share with the whole scene's placement
//! ([`distributed::whole_placement`]), so a glyph's float32 data is the same wherever it is
//! drawn. The combining is binary swap ([`binary_swap`]): each process sends at most one
//! image, however many processes there are.
//!
//! ```no_run
//! use ellipsoid_splat::{Camera, OffscreenRenderer, Outputs, Scene};
//! # fn share() -> (Scene, Vec<u32>) { unimplemented!() }
//! # fn camera() -> Camera { unimplemented!() }
//! let universe = mpi::initialize().expect("MPI starts once");
//! let world = universe.world();
//! let mut renderer = OffscreenRenderer::new(&Default::default())?;
//! let (part, global_ids) = share(); // this rank's glyphs and their indices in the whole
//! let done = ellipsoid_splat_mpi::render_composited(
//!     &world, 0, &mut renderer, &part, &global_ids, &camera(), Outputs::ALL,
//! )?;
//! if let Some(frame) = done.frame {
//!     // rank 0: the whole scene's frame
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! An application in another language hands over its communicator by its Fortran handle
//! ([`HostCommunicator`]) and its share as that language's arguments ([`share`]): the C ABI
//! (`crates/capi`, feature `mpi`) and the Python package (`crates/python`, feature `mpi`) draw
//! in situ through them.
//!
//! The core crate never links MPI; only this one does.
//!
//! # Files
//!
//! | what | where |
//! |---|---|
//! | sort-last compositing over MPI (`docs/mpi.md`): the key and pixel words, binary swap, the collective frame | `src/pixels.rs`, `binary_swap.rs`, `distributed.rs` |
//! | the MPI tests' driver and the compositing benchmark; 1-8 ranks under `mpirun` | `src/bin/composite-check.rs`, `composite-bench.rs`; `tests/mpirun.rs` |
//! | in situ over MPI (`docs/mpi.md`): the application's communicator by its Fortran handle, borrowed; every process learning of the first failure; a share made from another language's arguments, agreed on before drawing | `src/host_communicator.rs`, `failure.rs`, `share.rs` |

pub mod binary_swap;
pub mod distributed;
mod error;
pub mod failure;
mod host_communicator;
pub mod pixels;
pub mod share;

pub use distributed::{render_composited, Composited};
pub use error::{Error, Result};
pub use host_communicator::HostCommunicator;
pub use share::{render_share, Share, ShareError};

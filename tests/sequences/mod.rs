//! The parts of `tests/random_sequences.rs`, one concept each: the operations and their
//! strategies (`ops.rs`), the glyphs and cameras they name (`glyphs.rs`, `cameras.rs`), the
//! model of what each call answers (`model.rs`), the oracle every submitted pass is compared
//! with (`oracle.rs`), and the host that runs a sequence (`runner.rs`).

pub mod cameras;
pub mod glyphs;
pub mod model;
pub mod ops;
pub mod oracle;
pub mod runner;

//! Reporting for the `stress` (numerical-stability sweep) and `bench` (time-versus-error) commands:
//! PNG charts, aligned / Markdown / CSV tables, compact number formatting.
//!
//! - [`plot`]: [`line_chart`] (lines with markers and dashed [`Threshold`] bounds),
//!   [`scatter_chart`] (with an optional Pareto front) and [`bar_chart`], all 1200 x 800 PNG, on
//!   linear or log10 [`Axis`]es. Text uses DejaVuSans from Debian's `fonts-dejavu-core`
//!   ([`plot::FONT_PATH`], overridable with [`plot::FONT_ENV`]).
//! - [`table`]: [`format_table`], [`markdown_table`], [`write_csv`] and [`fmt_sci`].
//!
//! ```no_run
//! use std::path::Path;
//! use ellipsoid_splat_tool::report::{line_chart, Axis, Series, Threshold};
//! # fn main() -> ellipsoid_splat_tool::error::Result<()> {
//! let errors = Series::new("f32", vec![(1e-6, 2e-7), (1.0, 1.3e-7), (1e6, 4e-7)]);
//! line_chart(
//!     Path::new("stress.png"),
//!     "Depth error versus scale",
//!     &Axis::log("scene scale"),
//!     &Axis::log("max relative depth error"),
//!     &[errors],
//!     &[Threshold::new(1e-5, "bound 1e-5")],
//! )?;
//! # Ok(())
//! # }
//! ```

pub mod plot;
pub mod table;

pub use plot::{bar_chart, line_chart, scatter_chart, Axis, Series, Threshold};
pub use table::{fmt_sci, format_table, markdown_table, write_csv};

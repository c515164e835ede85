//! The frame plan as Python sees it: the mode by name, and the last frame's plan as a dict.

use ellipsoid_splat::FramePlan;
use ellipsoid_splat::{FramePath, HiddenLayers, PathKind, PlanMode, PlanReason};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The names a plan mode goes by, in the order the error message lists them.
const NAMES: &str = "'measure', 'estimate', 'draw', 'splat', 'visible-first'";

/// The mode `name` gives: `measure`, `estimate`, or a path kind's name to fix that path.
pub fn plan_mode(name: &str) -> PyResult<PlanMode> {
    match name {
        "measure" => Ok(PlanMode::Measure),
        "estimate" => Ok(PlanMode::Estimate),
        other => PathKind::from_name(other)
            .map(PlanMode::Fixed)
            .ok_or_else(|| {
                PyValueError::new_err(format!("plan must be one of {NAMES}, got {other:?}"))
            }),
    }
}

/// The name of `mode` ([`plan_mode`]'s inverse).
pub fn plan_name(mode: PlanMode) -> &'static str {
    match mode {
        PlanMode::Measure => "measure",
        PlanMode::Estimate => "estimate",
        PlanMode::Fixed(kind) => kind.name(),
    }
}

/// `plan` as a dict: `path`, `hidden`, `reason`, `reason_kind`, `measured_ms`, `runner_up`,
/// `runner_up_ms` and `candidates` (the Python half documents them).
pub fn plan_dict<'py>(py: Python<'py>, plan: &FramePlan) -> PyResult<Bound<'py, PyDict>> {
    let (path, hidden) = match plan.path {
        FramePath::Draw(_) => ("draw", None),
        FramePath::Splat(splat) => match splat.hidden {
            HiddenLayers::SplatAll => ("splat", Some("splat-all")),
            HiddenLayers::StampShown => ("visible-first", Some("stamp-shown")),
            HiddenLayers::VisibleFirst { .. } => ("visible-first", Some("visible-first")),
        },
    };
    let (kind, measured) = match plan.reason {
        PlanReason::Only(_) => ("only", None),
        PlanReason::Fixed => ("fixed", None),
        PlanReason::Estimated(_) => ("estimated", None),
        PlanReason::Measured(m) => ("measured", Some(m)),
        PlanReason::Exploring => ("exploring", None),
        // A reason a later library adds: the plan is still learning.
        _ => ("exploring", None),
    };
    let runner_up = measured.and_then(|m| m.runner_up);
    let dict = PyDict::new(py);
    dict.set_item("path", path)?;
    dict.set_item("hidden", hidden)?;
    dict.set_item("reason", plan.reason.to_string())?;
    dict.set_item("reason_kind", kind)?;
    dict.set_item("measured_ms", measured.map(|m| m.ms))?;
    dict.set_item("runner_up", runner_up.map(|(k, _)| k.name()))?;
    dict.set_item("runner_up_ms", runner_up.map(|(_, ms)| ms))?;
    let candidates: Vec<&str> = plan.candidates().into_iter().map(PathKind::name).collect();
    dict.set_item("candidates", candidates)?;
    Ok(dict)
}

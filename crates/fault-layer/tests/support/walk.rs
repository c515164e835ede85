//! The walk: a host's typical run through one API, first counted with no fault, then once
//! per fault point N with the N-th call failing, each run checked: the call hit returns the
//! named error, nothing panics, after running out of memory every later call works and draws
//! what a run without the failed call draws (bit for bit), after a loss every later call
//! works or reports the loss and draws nothing, and the teardown leaks nothing and raises no
//! validation message.

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use super::fault::Fault;

/// A frame as bits, so that two compare exactly.
pub type Bits = Vec<u32>;

/// One step of the run.
#[derive(Clone, Copy)]
pub struct Step {
    /// What the host does, for reports.
    pub name: &'static str,
    /// The suite's walk tries its fault points with the dense stride (the uploads, whose
    /// failures must keep the old scene, and the frames after the first), not the sparse one.
    pub dense: bool,
    /// It changes what later steps draw (an upload): when it fails, a run without it tells
    /// what they must draw. (A failed frame must change nothing.)
    pub changes: bool,
}

/// The steps of the typical run every API's walk follows, in order (each API's `Run` does
/// them its own way).
pub const TYPICAL_RUN: &[Step] = &[
    Step {
        name: "create",
        dense: false,
        changes: false,
    },
    Step {
        name: "upload",
        dense: true,
        changes: true,
    },
    Step {
        name: "frame 1",
        dense: false,
        changes: false,
    },
    Step {
        name: "frame 2",
        dense: true,
        changes: false,
    },
    Step {
        name: "update",
        dense: true,
        changes: true,
    },
    Step {
        name: "frame 3",
        dense: true,
        changes: false,
    },
    Step {
        name: "resize",
        dense: false,
        changes: false,
    },
    Step {
        name: "two views",
        dense: false,
        changes: false,
    },
    Step {
        name: "larger upload",
        dense: true,
        changes: true,
    },
    Step {
        name: "frame 4",
        dense: true,
        changes: false,
    },
];

/// A host's typical run through one API. Step 0 creates the renderer: when it fails, the
/// run ends there.
pub trait Run: Sized {
    /// What the API's calls fail with.
    type Error: std::fmt::Display;
    /// The run's steps, in order.
    fn steps() -> &'static [Step];
    /// A run before its first step.
    fn start() -> Self;
    /// Runs step `k`; a frame's bits where it draws one.
    fn step(&mut self, k: usize) -> Result<Option<Bits>, Self::Error>;
    /// The fault `error` names ([`Fault::OutOfMemory`] or [`Fault::DeviceLost`]), if it is
    /// one of those named errors.
    fn named(error: &Self::Error) -> Option<Fault>;
    /// Destroys everything; the error says what leaked or what validation reported.
    fn finish(self) -> Result<(), String>;
}

/// What a step gave: its frame (if it draws one), or its error's named fault and text.
type StepOutcome = Result<Option<Bits>, (Option<Fault>, String)>;

/// What one run gave: each step's frame or error text, the teardown's problem, and the
/// validation messages and leaks the library logged.
struct Outcome {
    steps: Vec<StepOutcome>,
    finish: Result<(), String>,
    logged: Vec<String>,
}

/// Runs `skip`ping a step (or none), catching panics as problems.
fn run<R: Run>(skip: Option<usize>, mut counted: impl FnMut(usize)) -> Result<Outcome, String> {
    super::log::take_problems(); // what earlier runs left
    let mut r = R::start();
    let mut steps = Vec::new();
    for (k, step) in R::steps().iter().enumerate() {
        if Some(k) == skip {
            steps.push(Ok(None));
            counted(k);
            continue;
        }
        let result = catch_unwind(AssertUnwindSafe(|| r.step(k)))
            .map_err(|p| format!("step '{}' panicked: {}", step.name, panic_text(&p)))?;
        counted(k);
        let failed_create = k == 0 && result.is_err();
        steps.push(result.map_err(|e| (R::named(&e), e.to_string())));
        if failed_create {
            break;
        }
    }
    let finish = catch_unwind(AssertUnwindSafe(|| r.finish()))
        .map_err(|p| format!("teardown panicked: {}", panic_text(&p)))?;
    let logged = super::log::take_problems();
    Ok(Outcome {
        steps,
        finish,
        logged,
    })
}

fn panic_text(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "no message".into())
}

/// How many fault points the suite's walk skips between two it tries: in the dense steps and
/// in the others. The first point of each step is always tried.
#[derive(Clone, Copy)]
pub struct Strides {
    pub dense: u64,
    pub sparse: u64,
}

/// The fault points the walk tries out of `ranges` (each step's first and last call): all
/// of them with `ES_FAULT_WALK=all`, else those `strides` choose. `ES_FAULT_POINTS=A-B` keeps
/// those from A to B (to look into one).
fn chosen(ranges: &[(u64, u64)], steps: &[Step], strides: Strides) -> Vec<u64> {
    let all = std::env::var("ES_FAULT_WALK").is_ok_and(|v| v == "all");
    let (low, high) = std::env::var("ES_FAULT_POINTS")
        .ok()
        .and_then(|v| {
            let (a, b) = v.split_once('-')?;
            Some((a.parse().ok()?, b.parse().ok()?))
        })
        .unwrap_or((1, u64::MAX));
    let mut points = Vec::new();
    for (&(first, last), step) in ranges.iter().zip(steps) {
        let stride = if step.dense {
            strides.dense
        } else {
            strides.sparse
        };
        for n in first..=last {
            if (all || (n - first) % stride == 0) && (low..=high).contains(&n) {
                points.push(n);
            }
        }
    }
    points
}

/// Walks `fault` over the run of `R`: asserts every check above at every chosen fault point,
/// and prints what it tried.
pub fn walk<R: Run>(fault: Fault, strides: Strides) {
    let start = Instant::now();
    // The counted run: each step's calls, its frames.
    fault.arm(0);
    let mut ranges = Vec::new();
    let mut before = 0;
    let mut step_start = Instant::now();
    let clean = run::<R>(None, |k| {
        let now = fault.count();
        ranges.push((before + 1, now));
        println!(
            "  {:<14} calls {:>4}..={now:<4} {:>6.0} ms",
            R::steps()[k].name,
            before + 1,
            step_start.elapsed().as_secs_f64() * 1e3
        );
        before = now;
        step_start = Instant::now();
    })
    .unwrap_or_else(|e| panic!("the fault-free run: {e}"));
    let total = fault.count();
    assert!(
        clean.finish.is_ok(),
        "the fault-free run: {:?}",
        clean.finish
    );
    assert!(
        clean.logged.is_empty(),
        "the fault-free run: {:?}",
        clean.logged
    );
    let reference: Vec<Option<Bits>> = clean
        .steps
        .into_iter()
        .enumerate()
        .map(|(k, s)| s.unwrap_or_else(|e| panic!("the fault-free run, step {k}: {}", e.1)))
        .collect();
    // The teardown's calls (after the last step) are fault points too.
    ranges.push((before + 1, total));
    let mut steps: Vec<Step> = R::steps().iter().map(|s| Step { ..*s }).collect();
    steps.push(Step {
        name: "teardown",
        dense: false,
        changes: false,
    });
    let points = chosen(&ranges, &steps, strides);

    // What runs without one step give, made when a step first fails: after running out of
    // memory a run must go on as if the failed call had not been made.
    let mut skipped: BTreeMap<usize, Vec<Result<Option<Bits>, String>>> = BTreeMap::new();
    let mut problems = Vec::new();
    // Per step and call hit: how often, and the error of the first.
    let mut hits: BTreeMap<String, (usize, String)> = BTreeMap::new();
    for &n in &points {
        fault.arm(n);
        let outcome = match run::<R>(None, |_| {}) {
            Ok(o) => o,
            Err(e) => {
                problems.push(format!("N = {n}: {e}"));
                continue;
            }
        };
        let fired = fault.fired();
        let Some(call) = fired else {
            problems.push(format!(
                "N = {n}: the fault never fired (the run made fewer calls than the counted one)"
            ));
            continue;
        };
        let first_failure = outcome.steps.iter().position(Result::is_err);
        let (place, error) = match first_failure {
            Some(k) => (
                steps[k].name,
                outcome.steps[k].as_ref().err().map(|e| e.1.clone()),
            ),
            None => ("(no step failed)", None),
        };
        let hit = hits.entry(format!("{place}: {call}")).or_default();
        hit.0 += 1;
        if hit.1.is_empty() {
            hit.1 = error.unwrap_or_default();
        }
        if let Some(f) = first_failure {
            if fault.named() == Fault::OutOfMemory && steps[f].changes && !skipped.contains_key(&f)
            {
                fault.arm(0);
                let without = run::<R>(Some(f), |_| {}).unwrap_or_else(|e| {
                    panic!("the fault-free run without '{}': {e}", steps[f].name)
                });
                let outcomes = without
                    .steps
                    .into_iter()
                    .map(|s| s.map_err(|e| e.1))
                    .collect();
                skipped.insert(f, outcomes);
            }
        }
        let mut problem = |what: String| problems.push(format!("N = {n} ({call}): {what}"));
        for (k, result) in outcome.steps.iter().enumerate() {
            let name = steps[k].name;
            let Some(f) = first_failure.filter(|&f| f <= k) else {
                // Before the fault showed (or it never did): as without a fault.
                if result.as_ref().ok() != Some(&reference[k]) {
                    problem(format!("'{name}' did not draw the fault-free picture"));
                }
                continue;
            };
            match (result, fault.named()) {
                (Err((named, text)), _) if k == f => {
                    if *named != Some(fault.named()) {
                        problem(format!(
                            "'{name}' failed with an error not named {fault:?}: {text}"
                        ));
                    }
                }
                (result, Fault::OutOfMemory | Fault::AllocatorFails) => {
                    let got = result.as_ref().map_err(|e| &e.1);
                    let expected = match skipped.get(&f) {
                        Some(without) => without[k].as_ref(),
                        None => Ok(&reference[k]),
                    };
                    if got != expected {
                        problem(format!(
                            "'{name}' after the failed '{}' did not do what it does without it: \
                             {}",
                            steps[f].name,
                            match got {
                                Ok(Some(_)) => "another picture".to_string(),
                                Ok(None) => "no picture".to_string(),
                                Err(text) => text.to_string(),
                            }
                        ));
                    }
                }
                (Ok(Some(_)), Fault::DeviceLost) => {
                    problem(format!("'{name}' drew a picture on the lost device"));
                }
                (Ok(None), Fault::DeviceLost) => {}
                (Err((named, text)), Fault::DeviceLost) => {
                    if *named != Some(Fault::DeviceLost) {
                        problem(format!("'{name}' on the lost device: {text}"));
                    }
                }
            }
        }
        if let Err(e) = outcome.finish {
            problem(format!("teardown: {e}"));
        }
        for logged in outcome.logged {
            problem(format!("logged: {logged}"));
        }
    }
    println!(
        "{fault:?}: {} of {total} fault points tried in {:.1} s; where they hit:",
        points.len(),
        start.elapsed().as_secs_f64()
    );
    for (place, (count, error)) in &hits {
        println!("  {count:4}  {place:<40} {error}");
    }
    assert!(
        problems.is_empty(),
        "{} problem(s):\n{}",
        problems.len(),
        problems.join("\n")
    );
}

//! The frame plan's regret on each bench scene: the time of the path the plan takes over the
//! time of the fastest of the fixed paths (`impostor-draw`, `impostor-compute`,
//! `impostor-visible-first`, each drawing the same exact picture), all timed in the same
//! interleaved rounds. Twice: for the first guess (`impostor-estimate`) and for the plan after
//! it learned the scene (`impostor`). 1 is the best there is; below 1 is the rounds' noise.
//! Where a fixed path was not timed on a scene, the fastest is unknown and no regret is given.

use ellipsoid_splat::research::Method;

use super::BenchResult;
use crate::report::markdown_table;

/// The plan's regret on one scene.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanRegret {
    /// Scene name.
    pub scene: String,
    /// Ellipsoids in the scene.
    pub count: usize,
    /// The fastest fixed path: its method, the path its frames took, its median time (ms);
    /// `None` where a fixed path was not timed.
    pub fastest: Option<(Method, String, f64)>,
    /// The fixed-path methods not timed on the scene (why `fastest` is unknown).
    pub untimed: Vec<Method>,
    /// The first guess (`impostor-estimate`): its path and regret, if it was timed.
    pub first_guess: Option<(String, Option<f64>)>,
    /// The plan after learning (`impostor`): its path, its regret, and how it learned.
    pub learned: Option<(String, Option<f64>, Option<super::Learning>)>,
}

/// The methods that fix the path, whose fastest the plan is measured against.
pub fn fixed_methods() -> Vec<Method> {
    Method::ALL
        .into_iter()
        .filter(|m| m.fixed_path().is_some())
        .collect()
}

/// The regret of every scene where `impostor` or `impostor-estimate` was timed.
pub fn plan_regrets(results: &[BenchResult]) -> Vec<PlanRegret> {
    let mut scenes: Vec<(&str, usize)> = Vec::new();
    for r in results {
        let key = (r.scene.as_str(), r.count);
        if matches!(r.method, Method::Impostor | Method::ImpostorEstimate) && !scenes.contains(&key)
        {
            scenes.push(key);
        }
    }
    scenes
        .into_iter()
        .map(|(scene, count)| {
            let row = |method: Method| {
                results
                    .iter()
                    .find(|r| r.method == method && r.scene == scene && r.count == count)
            };
            let fixed = fixed_methods();
            let untimed: Vec<Method> = fixed
                .iter()
                .copied()
                .filter(|&m| row(m).is_none())
                .collect();
            let fastest = if untimed.is_empty() {
                fixed
                    .iter()
                    .filter_map(|&m| row(m))
                    .min_by(|a, b| a.wall_ms.total_cmp(&b.wall_ms))
                    .map(|r| (r.method, r.plan_path(), r.wall_ms))
            } else {
                None
            };
            let regret = |r: &BenchResult| fastest.as_ref().map(|f| r.wall_ms / f.2);
            PlanRegret {
                scene: scene.to_string(),
                count,
                first_guess: row(Method::ImpostorEstimate).map(|r| (r.plan_path(), regret(r))),
                learned: row(Method::Impostor).map(|r| (r.plan_path(), regret(r), r.learning)),
                fastest,
                untimed,
            }
        })
        .collect()
}

/// The `plan_regret` cell of `result`'s row in `results.csv`: its regret on its scene if it is
/// `impostor` or `impostor-estimate` and the fastest fixed path is known, else empty.
pub fn regret_cell(regrets: &[PlanRegret], result: &BenchResult) -> String {
    let regret = regrets
        .iter()
        .find(|g| g.scene == result.scene && g.count == result.count)
        .and_then(|g| match result.method {
            Method::Impostor => g.learned.as_ref().and_then(|l| l.1),
            Method::ImpostorEstimate => g.first_guess.as_ref().and_then(|f| f.1),
            _ => None,
        });
    regret.map_or(String::new(), |x| format!("{x:.4}"))
}

/// The regret table (Markdown), with a note under it for each scene whose regret could not be
/// computed, and for a plan that had not settled when its timed rounds began.
pub fn regret_table(regrets: &[PlanRegret]) -> String {
    if regrets.is_empty() {
        return "no plan regret: neither impostor nor impostor-estimate was timed".into();
    }
    let ratio = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.2}"));
    let mut notes = Vec::new();
    let rows: Vec<Vec<String>> = regrets
        .iter()
        .map(|g| {
            let scene = format!("{} ({})", g.scene, g.count);
            if !g.untimed.is_empty() {
                let names: Vec<String> = g.untimed.iter().map(|m| m.name()).collect();
                notes.push(format!(
                    "{scene}: no regret -- {} not timed (left out of --methods, or skipped on \
                     the scene), so the fastest fixed path is unknown",
                    names.join(", ")
                ));
            }
            let learned_path = match &g.learned {
                None => "-".to_string(),
                Some((path, _, Some(l))) if l.settled => {
                    format!("{path} (settled in {} frames)", l.frames)
                }
                Some((path, _, Some(l))) => {
                    notes.push(format!(
                        "{scene}: impostor had not settled after {} frames; its rounds may mix \
                         paths",
                        l.frames
                    ));
                    format!("{path} (not settled)")
                }
                Some((path, _, None)) => path.clone(),
            };
            vec![
                scene,
                g.first_guess.as_ref().map_or("-".into(), |f| f.0.clone()),
                ratio(g.first_guess.as_ref().and_then(|f| f.1)),
                learned_path,
                ratio(g.learned.as_ref().and_then(|l| l.1)),
                g.fastest.as_ref().map_or("-".into(), |(m, path, ms)| {
                    format!("{path} ({}, {ms:.2} ms)", m.name())
                }),
            ]
        })
        .collect();
    let mut text = markdown_table(
        &[
            "scene",
            "first guess",
            "regret",
            "learned",
            "regret",
            "fastest fixed path",
        ],
        &rows,
    );
    for note in notes {
        text.push_str(&format!("\nnote: {note}"));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::Learning;

    fn result(method: Method, wall_ms: f64, path: &'static str) -> BenchResult {
        BenchResult {
            method,
            scene: "liquid".into(),
            count: 8000,
            size: (1920, 1080),
            size_px: 0.0,
            wall_ms,
            wall_quartiles_ms: (wall_ms, wall_ms),
            gpu_ms: wall_ms,
            fragments: 0,
            shaded_pixels: None,
            ray_casts: None,
            silhouette_pixels: 0,
            stats: Default::default(),
            paths: vec![path],
            learning: (method == Method::Impostor).then_some(Learning {
                frames: 17,
                settled: true,
            }),
            motion: crate::bench::Motion::Still,
        }
    }

    fn all_five() -> Vec<BenchResult> {
        vec![
            result(Method::Impostor, 36.0, "splat"),
            result(Method::ImpostorEstimate, 60.0, "draw"),
            result(Method::ImpostorDraw, 61.0, "draw"),
            result(Method::ImpostorCompute, 35.0, "splat"),
            result(Method::ImpostorVisibleFirst, 40.0, "visible-first"),
        ]
    }

    #[test]
    fn regret_is_time_over_the_fastest_fixed_path() {
        let results = all_five();
        let regrets = plan_regrets(&results);
        assert_eq!(regrets.len(), 1);
        let g = &regrets[0];
        assert_eq!(
            g.fastest,
            Some((Method::ImpostorCompute, "splat".to_string(), 35.0))
        );
        assert_eq!(g.first_guess, Some(("draw".into(), Some(60.0 / 35.0))));
        assert_eq!(g.learned.as_ref().map(|l| l.1), Some(Some(36.0 / 35.0)));
        assert_eq!(regret_cell(&regrets, &results[0]), "1.0286");
        assert_eq!(regret_cell(&regrets, &results[1]), "1.7143");
        assert_eq!(
            regret_cell(&regrets, &results[2]),
            "",
            "only the plan's rows"
        );
        let table = regret_table(&regrets);
        assert!(table.contains("splat (settled in 17 frames)"), "{table}");
        assert!(
            table.contains("splat (impostor-compute, 35.00 ms)"),
            "{table}"
        );
        assert!(!table.contains("note:"), "{table}");
    }

    #[test]
    fn without_every_fixed_path_there_is_no_regret_and_a_note_says_why() {
        let results: Vec<BenchResult> = all_five()
            .into_iter()
            .filter(|r| r.method != Method::ImpostorVisibleFirst)
            .collect();
        let regrets = plan_regrets(&results);
        assert_eq!(regrets[0].fastest, None);
        assert_eq!(regrets[0].untimed, vec![Method::ImpostorVisibleFirst]);
        assert_eq!(regret_cell(&regrets, &results[0]), "");
        let table = regret_table(&regrets);
        assert!(
            table.contains("note: liquid (8000): no regret -- impostor-visible-first not timed"),
            "{table}"
        );
        // No plan timed at all: nothing to say per scene.
        let fixed_only: Vec<BenchResult> = all_five().into_iter().skip(2).collect();
        assert!(plan_regrets(&fixed_only).is_empty());
        assert!(regret_table(&[]).starts_with("no plan regret"));
    }
}

//! PNG charts for the `stress` and `bench` reports: line charts with error bounds, scatter plots
//! with a Pareto front, and bar charts.
//!
//! Every chart is [`WIDTH`] x [`HEIGHT`] pixels, white background, title on top, legend in a
//! panel right of the plot (so it never hides data). Axes are linear or base-10 logarithmic
//! ([`Axis::log`]), plotters' own coordinates and ticks (`RangedCoordf64`, `LogCoord`) with this
//! module's labels; a log axis spans whatever the data spans (1e-12..1e7 is fine) and silently
//! skips points it cannot show (zero, negative, NaN, infinite), as a linear axis skips non-finite
//! ones. A chart with no drawable point still renders, with "no data" in the plot.
//!
//! Drawing uses `plotters`' bitmap backend into memory, encoded to PNG by the `image` crate. Text
//! is rasterised by the pure-Rust `ab_glyph` from a TrueType file read at run time:
//! [`FONT_PATH`] (Debian package `fonts-dejavu-core`, installed by `scripts/setup.sh`), or the
//! file named by the environment variable [`FONT_ENV`]. Without a font every chart function
//! fails with an [`Error::Encode`] naming the font file and the `apt-get` fix.

use std::ops::Range;
use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::ranged1d::{BoldPoints, KeyPointHint, KeyPointWeight};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::error::{Error, Result};

use super::table::fmt_sci_digits;

/// Width of every chart in pixels.
pub const WIDTH: u32 = 1200;
/// Height of every chart in pixels.
pub const HEIGHT: u32 = 800;

/// The TrueType font used for all text (Debian 12: package `fonts-dejavu-core`).
pub const FONT_PATH: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
/// Bold face for titles; optional (titles fall back to [`FONT_PATH`]).
const BOLD_FONT_PATH: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf";
/// Environment variable naming another TrueType/OpenType file to use instead of [`FONT_PATH`].
pub const FONT_ENV: &str = "ELLIPSOID_SPLAT_FONT";

/// The family name the font is registered under; plotters' own defaults also ask for it.
const FAMILY: &str = "sans-serif";

/// One named set of `(x, y)` points.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// The points, in drawing order (a line chart joins them in this order).
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A series from a name and its points.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
        }
    }
}

/// How one axis is labelled and scaled.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Axis description, e.g. `"relative depth error"`.
    pub label: String,
    /// Base-10 logarithmic scale; values that are not positive and finite are skipped.
    pub log: bool,
}

impl Axis {
    /// A linear axis.
    pub fn linear(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            log: false,
        }
    }

    /// A base-10 logarithmic axis.
    pub fn log(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            log: true,
        }
    }
}

/// A horizontal reference line at `y = value` (e.g. an error bound), drawn dashed with `label`
/// written above its right end. The y range always includes it (unless a log axis cannot show it).
#[derive(Debug, Clone, PartialEq)]
pub struct Threshold {
    /// The y value.
    pub value: f64,
    /// Text beside the line, e.g. `"bound 1e-6"`.
    pub label: String,
}

impl Threshold {
    /// A threshold from its value and label.
    pub fn new(value: f64, label: impl Into<String>) -> Self {
        Self {
            value,
            label: label.into(),
        }
    }
}

/// A chart of lines with point markers, one per series, plus dashed `thresholds`.
///
/// Colours are distinct for the first ten series; after that the colours repeat with another
/// marker shape. Points an axis cannot show are skipped and the line joins the remaining ones.
pub fn line_chart(
    path: &Path,
    title: &str,
    x: &Axis,
    y: &Axis,
    series: &[Series],
    thresholds: &[Threshold],
) -> Result<()> {
    xy_chart(
        path,
        &XyChart {
            title,
            x,
            y,
            series,
            lines: true,
            thresholds,
            front: None,
        },
    )
}

/// A scatter plot: the points of each series as markers, with a legend; `front` (e.g. the Pareto
/// front of time versus error) is drawn as a black line through its points, sorted by x.
pub fn scatter_chart(
    path: &Path,
    title: &str,
    x: &Axis,
    y: &Axis,
    series: &[Series],
    front: Option<&[(f64, f64)]>,
) -> Result<()> {
    xy_chart(
        path,
        &XyChart {
            title,
            x,
            y,
            series,
            lines: false,
            thresholds: &[],
            front,
        },
    )
}

/// A bar chart: one bar per `(name, value)`, names under the bars and values on top.
///
/// On a linear axis bars start at zero (and may go below it); on a log axis they rise from the
/// bottom of the axis. A bar the axis cannot show (zero or negative on a log axis, NaN, infinite)
/// is left out; its name stays and its value is written in grey at the base.
pub fn bar_chart(path: &Path, title: &str, y: &Axis, bars: &[(String, f64)]) -> Result<()> {
    render(path, |root| {
        let area = root
            .margin(8, 0, 0, 0)
            .titled(title, title_style())
            .map_err(text)?;
        let shown: Vec<(usize, f64)> = bars
            .iter()
            .enumerate()
            .filter(|(_, (_, v))| usable(*v, y.log))
            .map(|(i, (_, v))| (i, *v))
            .collect();
        let values = shown.iter().map(|&(_, v)| v);
        let ys = if y.log {
            // Room below the smallest bar so that it shows, and above the tallest for its label.
            Scale::fit(values, true, 0.08)
        } else {
            // Bars start at zero, so zero is in range; pad away from it only.
            Scale::fit(values.chain([0.0]), false, 0.0).pad_linear(0.08)
        };
        let names: Vec<String> = bars.iter().map(|(n, _)| n.clone()).collect();
        let xs = Scale::categories(names);

        let mut chart = ChartBuilder::on(&area)
            .margin(20)
            .x_label_area_size(70)
            .y_label_area_size(y_label_area(&area, &ys)?)
            .build_cartesian_2d(xs.clone(), ys.clone())
            .map_err(text)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(xs.len().max(1))
            .y_labels(N_LABELS)
            .y_desc(y.label.as_str())
            .label_style(label_style())
            .axis_desc_style(axis_desc_style())
            .light_line_style(LIGHT_GRID)
            .bold_line_style(BOLD_GRID)
            .draw()
            .map_err(text)?;

        let base = if y.log { ys.lo } else { 0.0 };
        let plot = chart.plotting_area();
        // Values the axis cannot show get their value written at the base instead of a bar.
        for (i, (_, v)) in bars.iter().enumerate() {
            if !usable(*v, y.log) {
                plot.draw(
                    &(EmptyElement::at((i as f64, base))
                        + Text::new(
                            fmt_value(*v),
                            (0, -4),
                            label_style()
                                .color(&THRESHOLD_COLOUR)
                                .pos(Pos::new(HPos::Center, VPos::Bottom)),
                        )),
                )
                .map_err(text)?;
            }
        }
        for &(i, v) in &shown {
            let c = i as f64;
            let colour = PALETTE[i % PALETTE.len()];
            plot.draw(&Rectangle::new(
                [(c - 0.35, base), (c + 0.35, v)],
                colour.filled(),
            ))
            .map_err(text)?;
            let pos = if v >= base {
                Pos::new(HPos::Center, VPos::Bottom)
            } else {
                Pos::new(HPos::Center, VPos::Top)
            };
            let offset = if v >= base { -4 } else { 4 };
            plot.draw(
                &(EmptyElement::at((c, v))
                    + Text::new(fmt_value(v), (0, offset), label_style().pos(pos))),
            )
            .map_err(text)?;
        }
        if shown.is_empty() {
            no_data(plot, &xs, &ys)?;
        }
        Ok(())
    })
}

/// Number of bold grid lines / tick labels asked for on each axis.
const N_LABELS: usize = 10;
const LIGHT_GRID: RGBColor = RGBColor(238, 238, 238);
const BOLD_GRID: RGBColor = RGBColor(205, 205, 205);
const THRESHOLD_COLOUR: RGBColor = RGBColor(90, 90, 90);

/// Ten distinct colours (the "Tableau 10" palette).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Marker shapes; series 10..19 use the second, and so on.
#[derive(Debug, Clone, Copy)]
enum Marker {
    Circle,
    Square,
    Triangle,
    Cross,
}

/// Colour and marker of series `i`.
fn series_style(i: usize) -> (RGBColor, Marker) {
    let shapes = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
    ];
    (
        PALETTE[i % PALETTE.len()],
        shapes[(i / PALETTE.len()) % shapes.len()],
    )
}

fn title_style() -> TextStyle<'static> {
    // `FontDesc::style` keeps the regular face's glyphs; `new` looks the bold face up.
    FontDesc::new(FontFamily::Name(FAMILY), 28.0, FontStyle::Bold).into()
}

fn label_style() -> TextStyle<'static> {
    (FAMILY, 16).into_font().into()
}

fn axis_desc_style() -> TextStyle<'static> {
    (FAMILY, 20).into_font().into()
}

fn legend_style() -> TextStyle<'static> {
    (FAMILY, 17).into_font().into()
}

/// Any displayable error as the `reason` of an [`Error::Encode`].
fn text(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// Whether `v` can be drawn on a (log) axis.
fn usable(v: f64, log: bool) -> bool {
    v.is_finite() && (!log || v > 0.0)
}

/// Loads and registers the font once per process; the error names the file and the fix.
fn ensure_font() -> std::result::Result<(), String> {
    static FONT: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    FONT.get_or_init(|| {
        let (path, from_env) = match std::env::var_os(FONT_ENV) {
            Some(p) if !p.is_empty() => (std::path::PathBuf::from(p), true),
            _ => (std::path::PathBuf::from(FONT_PATH), false),
        };
        let bytes = read_font(&path, from_env)?;
        // plotters keeps registered fonts for the life of the process and wants `'static`
        // data: the file is read once per process, so leaking it is bounded.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font(FAMILY, FontStyle::Normal, bytes).map_err(|_| {
            format!(
                "font {} is not a valid TrueType/OpenType file",
                path.display()
            )
        })?;
        if !from_env {
            if let Ok(bold) = std::fs::read(BOLD_FONT_PATH) {
                let bold: &'static [u8] = Box::leak(bold.into_boxed_slice());
                // Optional: without it titles use the regular face.
                let _ = plotters::style::register_font(FAMILY, FontStyle::Bold, bold);
            }
        }
        Ok(())
    })
    .clone()
}

/// Reads a font file; the error names the file and, for the default font, the Debian package.
fn read_font(path: &Path, from_env: bool) -> std::result::Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| {
        if from_env {
            format!("cannot read font {} (from {FONT_ENV}): {e}", path.display())
        } else {
            format!(
                "cannot read font {}: {e}; on Debian: apt-get install fonts-dejavu-core \
                 (or set {FONT_ENV} to a TrueType font file)",
                path.display()
            )
        }
    })
}

/// Draws a chart with `draw` into a white [`WIDTH`] x [`HEIGHT`] RGB buffer and writes it as PNG.
fn render(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> std::result::Result<(), String>,
) -> Result<()> {
    let encode = |reason: String| Error::Encode {
        path: path.to_path_buf(),
        reason,
    };
    ensure_font().map_err(encode)?;
    let mut buffer = vec![255u8; WIDTH as usize * HEIGHT as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| encode(text(e)))?;
        draw(&root).map_err(encode)?;
        root.present().map_err(|e| encode(text(e)))?;
    }
    if buffer.len() != WIDTH as usize * HEIGHT as usize * 3 {
        return Err(encode("chart buffer has the wrong size".to_string()));
    }
    crate::output::write_file(path, |w| {
        use image::ImageEncoder;
        image::codecs::png::PngEncoder::new(w)
            .write_image(&buffer, WIDTH, HEIGHT, image::ExtendedColorType::Rgb8)
            .map_err(std::io::Error::other)
    })
}

/// Everything a line or scatter chart draws.
struct XyChart<'a> {
    title: &'a str,
    x: &'a Axis,
    y: &'a Axis,
    series: &'a [Series],
    /// Join each series' points with a line (line chart) or not (scatter).
    lines: bool,
    thresholds: &'a [Threshold],
    front: Option<&'a [(f64, f64)]>,
}

/// One row of the legend panel.
struct LegendEntry {
    name: String,
    colour: RGBColor,
    marker: Option<Marker>,
    line: bool,
}

fn xy_chart(path: &Path, c: &XyChart<'_>) -> Result<()> {
    let keep = |&(px, py): &(f64, f64)| usable(px, c.x.log) && usable(py, c.y.log);
    let series: Vec<Vec<(f64, f64)>> = c
        .series
        .iter()
        .map(|s| s.points.iter().copied().filter(keep).collect())
        .collect();
    let mut front: Vec<(f64, f64)> = c
        .front
        .unwrap_or(&[])
        .iter()
        .copied()
        .filter(keep)
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let thresholds: Vec<&Threshold> = c
        .thresholds
        .iter()
        .filter(|t| usable(t.value, c.y.log))
        .collect();

    let all = || series.iter().flatten().chain(&front);
    let xs = Scale::fit(all().map(|p| p.0), c.x.log, 0.04);
    let ys = Scale::fit(
        all().map(|p| p.1).chain(thresholds.iter().map(|t| t.value)),
        c.y.log,
        0.05,
    );

    let mut legend: Vec<LegendEntry> = c
        .series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let (colour, marker) = series_style(i);
            LegendEntry {
                name: s.name.clone(),
                colour,
                marker: Some(marker),
                line: c.lines,
            }
        })
        .collect();
    if c.front.is_some() {
        legend.push(LegendEntry {
            name: "Pareto front".to_string(),
            colour: BLACK,
            marker: None,
            line: true,
        });
    }

    render(path, |root| {
        let area = root
            .margin(8, 0, 0, 0)
            .titled(c.title, title_style())
            .map_err(text)?;
        let (main, side) = split_legend(&area, &legend)?;
        let mut chart = ChartBuilder::on(&main)
            .margin(20)
            .x_label_area_size(60)
            .y_label_area_size(y_label_area(&main, &ys)?)
            .build_cartesian_2d(xs.clone(), ys.clone())
            .map_err(text)?;
        chart
            .configure_mesh()
            .x_labels(N_LABELS)
            .y_labels(N_LABELS)
            .x_desc(c.x.label.as_str())
            .y_desc(c.y.label.as_str())
            .label_style(label_style())
            .axis_desc_style(axis_desc_style())
            .light_line_style(LIGHT_GRID)
            .bold_line_style(BOLD_GRID)
            .draw()
            .map_err(text)?;
        let plot = chart.plotting_area();

        for t in &thresholds {
            plot.draw(&DashedPathElement::new(
                [(xs.lo, t.value), (xs.hi, t.value)],
                10,
                6,
                THRESHOLD_COLOUR.stroke_width(2),
            ))
            .map_err(text)?;
            plot.draw(
                &(EmptyElement::at((xs.hi, t.value))
                    + Text::new(
                        t.label.clone(),
                        (-8, -5),
                        label_style()
                            .color(&THRESHOLD_COLOUR)
                            .pos(Pos::new(HPos::Right, VPos::Bottom)),
                    )),
            )
            .map_err(text)?;
        }

        if !front.is_empty() {
            plot.draw(&PathElement::new(front.clone(), BLACK.stroke_width(2)))
                .map_err(text)?;
            for &p in &front {
                plot.draw(&Circle::new(p, 3, BLACK.filled()))
                    .map_err(text)?;
            }
        }

        for (i, points) in series.iter().enumerate() {
            let (colour, marker) = series_style(i);
            if c.lines && points.len() > 1 {
                plot.draw(&PathElement::new(points.clone(), colour.stroke_width(2)))
                    .map_err(text)?;
            }
            for &p in points {
                draw_marker(plot, p, marker, colour)?;
            }
        }

        if all().next().is_none() {
            no_data(plot, &xs, &ys)?;
        }
        if let Some(side) = side {
            draw_legend(&side, &legend)?;
        }
        Ok(())
    })
}

/// The whole image or a pixel-addressed part of it.
type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// Splits off a right-hand legend panel as wide as the longest entry needs (at most 40 % of the
/// chart); no panel without entries.
fn split_legend<'a>(
    area: &Area<'a>,
    legend: &[LegendEntry],
) -> std::result::Result<(Area<'a>, Option<Area<'a>>), String> {
    if legend.is_empty() {
        return Ok((area.clone(), None));
    }
    let mut widest = 0;
    for entry in legend {
        widest = widest.max(
            area.estimate_text_size(&entry.name, &legend_style())
                .map_err(text)?
                .0,
        );
    }
    let (w, _) = area.dim_in_pixel();
    let panel = (widest + 70).min(w * 2 / 5);
    let (main, side) = area.split_horizontally(w - panel);
    Ok((main, Some(side)))
}

/// Draws the legend entries top-down in `side`: a line and/or marker, then the name (cut to fit).
fn draw_legend(side: &Area<'_>, legend: &[LegendEntry]) -> std::result::Result<(), String> {
    let (w, h) = side.dim_in_pixel();
    let top = 40;
    // Rows shrink (to no less than the text's height) so that a long legend stays inside.
    let fits = (h as i32 - top - 10) / (legend.len() as i32).max(1);
    let row = fits.clamp(18, 28);
    let text_x = 50;
    let room = w.saturating_sub(text_x as u32 + 10);
    side.draw(&Rectangle::new(
        [
            (2, top - row / 2 - 4),
            (w as i32 - 8, top + row * legend.len() as i32 - row / 2 + 4),
        ],
        BOLD_GRID.stroke_width(1),
    ))
    .map_err(text)?;
    for (k, entry) in legend.iter().enumerate() {
        let y = top + row * k as i32;
        if entry.line {
            side.draw(&PathElement::new(
                [(10, y), (40, y)],
                entry.colour.stroke_width(2),
            ))
            .map_err(text)?;
        }
        if let Some(marker) = entry.marker {
            draw_marker(side, (25, y), marker, entry.colour)?;
        }
        let mut name = entry.name.clone();
        while !name.is_empty()
            && side
                .estimate_text_size(&name, &legend_style())
                .map_err(text)?
                .0
                > room
        {
            name.pop();
            name = format!("{}…", name.trim_end_matches('…'));
            if name == "…" {
                break;
            }
        }
        side.draw(&Text::new(
            name,
            (text_x, y),
            legend_style().pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(text)?;
    }
    Ok(())
}

/// Draws one marker centred on `at`, in any coordinate system.
fn draw_marker<CT>(
    area: &DrawingArea<BitMapBackend<'_>, CT>,
    at: CT::From,
    marker: Marker,
    colour: RGBColor,
) -> std::result::Result<(), String>
where
    CT: plotters::coord::CoordTranslate,
    CT::From: Clone,
{
    let fill = colour.filled();
    match marker {
        Marker::Circle => area.draw(&Circle::new(at, 4, fill)),
        Marker::Square => {
            area.draw(&(EmptyElement::at(at) + Rectangle::new([(-4, -4), (4, 4)], fill)))
        }
        Marker::Triangle => area.draw(&TriangleMarker::new(at, 6, fill)),
        Marker::Cross => area.draw(&Cross::new(at, 5, colour.stroke_width(2))),
    }
    .map_err(text)
}

/// Writes "no data" in the middle of an empty plot.
fn no_data(
    plot: &DrawingArea<BitMapBackend<'_>, Cartesian2d<Scale, Scale>>,
    xs: &Scale,
    ys: &Scale,
) -> std::result::Result<(), String> {
    plot.draw(&Text::new(
        "no data",
        (xs.mid(), ys.mid()),
        (FAMILY, 24)
            .into_font()
            .color(&RGBColor(150, 150, 150))
            .pos(Pos::new(HPos::Center, VPos::Center)),
    ))
    .map_err(text)
}

/// Width for the y tick labels plus the rotated axis description.
fn y_label_area(area: &Area<'_>, ys: &Scale) -> std::result::Result<u32, String> {
    let mut widest = 0;
    for v in ys.majors(N_LABELS) {
        widest = widest.max(
            area.estimate_text_size(&ys.label(v), &label_style())
                .map_err(text)?
                .0,
        );
    }
    Ok(widest + 50)
}

/// A general-purpose number for bar values: plain decimals for ordinary magnitudes, [`fmt_sci`]
/// style otherwise.
///
/// [`fmt_sci`]: super::fmt_sci
fn fmt_value(v: f64) -> String {
    if v == 0.0 || (1e-3..1e5).contains(&v.abs()) {
        plain(v, 4)
    } else {
        fmt_sci_digits(v, 3)
    }
}

/// `v` rounded to `digits` significant digits, printed as a plain decimal without trailing zeros.
fn plain(v: f64, digits: usize) -> String {
    let rounded: f64 = fmt_sci_digits(v, digits).parse().unwrap_or(v);
    let s = format!("{rounded}");
    if s == "-0" {
        "0".to_string()
    } else {
        s
    }
}

/// How an axis maps values: linear, log10, or named categories at 0, 1, 2, ...
#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Linear,
    Log,
    Categories(Vec<String>),
}

/// One axis of a chart: plotters' linear (`RangedCoordf64`) or logarithmic (`LogCoord`)
/// coordinates, or named categories, with this module's tick labels. One concrete type keeps
/// the chart code free of generics; the mapping and the ticks are plotters' own.
#[derive(Debug, Clone, PartialEq)]
struct Scale {
    kind: Kind,
    lo: f64,
    hi: f64,
    /// Tick labels: plain decimals (`None`) or scientific with this many significant digits.
    sci_digits: Option<usize>,
}

impl Scale {
    /// A range covering `values` (already filtered to what the axis can show) with `pad` of the
    /// span (in decades on a log axis) added on each side; a default range when there is none.
    fn fit(values: impl Iterator<Item = f64>, log: bool, pad: f64) -> Self {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|&v| usable(v, log)) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        let (lo, hi) = if lo > hi {
            if log {
                (1.0, 10.0)
            } else {
                (0.0, 1.0)
            }
        } else if log {
            let (a, b) = (lo.log10(), hi.log10());
            let (a, b) = if b - a < 1e-9 {
                (a - 0.5, b + 0.5)
            } else {
                let p = pad * (b - a).max(1.0);
                (a - p, b + p)
            };
            (
                10f64.powf(a).max(f64::MIN_POSITIVE),
                10f64.powf(b).min(f64::MAX),
            )
        } else if hi - lo <= 1e-12 * lo.abs().max(hi.abs()) || lo == hi {
            let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
            (lo - d, hi + d)
        } else {
            let span = hi - lo;
            if span.is_finite() {
                (lo - pad * span, hi + pad * span)
            } else {
                (lo, hi)
            }
        };
        let kind = if log { Kind::Log } else { Kind::Linear };
        Self::with_labels(kind, lo, hi)
    }

    /// A categorical axis for `names` at x = 0, 1, ....
    fn categories(names: Vec<String>) -> Self {
        let n = names.len().max(1) as f64;
        Self::with_labels(Kind::Categories(names), -0.5, n - 0.5)
    }

    /// Widens a linear range by `pad` of its span on each side, keeping zero where it is when it
    /// is an end of the range (bars start there).
    fn pad_linear(mut self, pad: f64) -> Self {
        let span = self.hi - self.lo;
        if self.lo != 0.0 {
            self.lo -= pad * span;
        }
        if self.hi != 0.0 {
            self.hi += pad * span;
        }
        Self::with_labels(self.kind, self.lo, self.hi)
    }

    /// Chooses the tick label format: plain decimals when every major tick is 0 or within
    /// 1e-3..1e5 in magnitude, else scientific with the fewest digits that tell ticks apart.
    fn with_labels(kind: Kind, lo: f64, hi: f64) -> Self {
        let mut s = Self {
            kind,
            lo,
            hi,
            sci_digits: None,
        };
        if matches!(s.kind, Kind::Categories(_)) {
            return s;
        }
        let majors = s.majors(N_LABELS);
        if majors
            .iter()
            .all(|&v| v == 0.0 || (1e-3..1e5).contains(&v.abs()))
        {
            return s;
        }
        let digits = (1..=15)
            .find(|&d| {
                let labels: Vec<String> = majors.iter().map(|&v| fmt_sci_digits(v, d)).collect();
                labels.windows(2).all(|w| w[0] != w[1])
            })
            .unwrap_or(15);
        s.sci_digits = Some(digits);
        s
    }

    /// Plotters' linear coordinates over the range (also the categories' positions).
    fn linear(&self) -> RangedCoordf64 {
        (self.lo..self.hi).into()
    }

    /// Plotters' base-10 logarithmic coordinates over the range.
    fn log(&self) -> LogCoord<f64> {
        (self.lo..self.hi).log_scale().into()
    }

    /// Number of categories (0 for a numeric axis).
    fn len(&self) -> usize {
        match &self.kind {
            Kind::Categories(names) => names.len(),
            _ => 0,
        }
    }

    /// The value halfway along the axis.
    fn mid(&self) -> f64 {
        match self.kind {
            Kind::Log => (self.lo * self.hi).sqrt(),
            _ => 0.5 * (self.lo + self.hi),
        }
    }

    /// The tick label of `v`.
    fn label(&self, v: f64) -> String {
        match (&self.kind, self.sci_digits) {
            (Kind::Categories(names), _) => {
                let i = v.round();
                if i >= 0.0 && (i as usize) < names.len() {
                    names[i as usize].clone()
                } else {
                    String::new()
                }
            }
            (_, Some(d)) => fmt_sci_digits(v, d),
            (_, None) => plain(v, 12),
        }
    }

    /// Plotters' log ticks (it ignores the hint's weight). They start at the first power of
    /// ten inside the range, leaving the part below it bare (0.12..2 gets 1 and 2 only), so
    /// they are also taken from the whole decade the range starts in, and the set with more
    /// ticks inside the range kept; a tick plotters gives twice (10 ends 1..10 and starts
    /// 10..100) is kept once.
    fn log_key_points(&self, max: usize) -> Vec<f64> {
        // A hair below the power of ten, which plotters' rounding could otherwise skip.
        let decade = (10f64.powf(self.lo.log10().floor()) * 0.999_999).max(f64::MIN_POSITIVE);
        [self.lo, decade]
            .map(|lo| {
                let coord: LogCoord<f64> = (lo..self.hi).log_scale().into();
                let mut points = coord.key_points(max);
                points.retain(|&v| v >= self.lo * (1.0 - 1e-12) && v <= self.hi * (1.0 + 1e-12));
                points.sort_by(f64::total_cmp);
                points.dedup_by(|a, b| (*a / *b - 1.0).abs() < 1e-9);
                points
            })
            .into_iter()
            .max_by_key(Vec::len)
            .unwrap_or_default()
    }

    /// The labelled ticks, at most `max`.
    fn majors(&self, max: usize) -> Vec<f64> {
        self.key_points(BoldPoints(max))
    }
}

impl Ranged for Scale {
    type FormatOption = plotters::coord::ranged1d::NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        match self.kind {
            Kind::Log => self.log().map(value, limit),
            _ => self.linear().map(value, limit),
        }
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        match &self.kind {
            Kind::Log => {
                let (max, weight) = (hint.max_num_points(), hint.weight());
                let points = self.log_key_points(max);
                // Within less than a decade there may be no such tick to label; the linear
                // ticks of the same range label it instead.
                match weight {
                    _ if points.len() >= 2 || max < 2 => points,
                    KeyPointWeight::Bold => self.linear().key_points(BoldPoints(max)),
                    KeyPointWeight::Any => self.linear().key_points(max),
                }
            }
            Kind::Linear => self.linear().key_points(hint),
            // One tick per category, every k-th when there are more than the hint allows.
            Kind::Categories(names) => match hint.weight() {
                KeyPointWeight::Bold => {
                    let step = names.len().div_ceil(hint.max_num_points().max(1)).max(1);
                    (0..names.len()).step_by(step).map(|i| i as f64).collect()
                }
                KeyPointWeight::Any => Vec::new(),
            },
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl plotters::coord::ranged1d::ValueFormatter<f64> for Scale {
    fn format_ext(&self, value: &f64) -> String {
        self.label(*value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh path in the temp directory for this test process.
    fn temp_png(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("ellipsoid-splat-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// Decodes the PNG at `path`, checks its size, removes it and returns how many pixels are
    /// not white (to tell a drawn chart from a blank image).
    fn check_png(path: &Path) -> usize {
        let img = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!((img.width(), img.height()), (WIDTH, HEIGHT));
        let ink = img
            .to_rgb8()
            .pixels()
            .filter(|p| p.0 != [255, 255, 255])
            .count();
        std::fs::remove_file(path).unwrap();
        ink
    }

    fn wide_series() -> Vec<Series> {
        let sizes = [1e-12, 1e-9, 1e-6, 1e-3, 1.0, 1e3, 1e7];
        vec![
            Series::new(
                "f32 silhouette frame",
                sizes
                    .iter()
                    .map(|&s: &f64| (s, 1e-7 * (1.0 + s.log10().abs())))
                    .collect(),
            ),
            Series::new(
                "naive quadratic",
                sizes
                    .iter()
                    .map(|&s| (s, 1e-7 * s.powf(-0.5).max(1.0)))
                    .collect(),
            ),
            // A zero and a NaN on the log y axis: skipped, not a panic.
            Series::new(
                "with zero",
                vec![(1e-6, 0.0), (1.0, 1e-3), (1e3, f64::NAN), (1e6, 2e-3)],
            ),
        ]
    }

    #[test]
    fn line_chart_log_axes_wide_range() {
        let path = temp_png("line.png");
        line_chart(
            &path,
            "Depth error versus ellipsoid size",
            &Axis::log("ellipsoid size"),
            &Axis::log("relative depth error"),
            &wide_series(),
            &[
                Threshold::new(1e-5, "bound 1e-5"),
                Threshold::new(0.0, "unshowable"),
            ],
        )
        .unwrap();
        assert!(check_png(&path) > 10_000);
    }

    #[test]
    fn line_chart_linear_and_many_series() {
        let path = temp_png("line_many.png");
        let series: Vec<Series> = (0..14)
            .map(|i| {
                Series::new(
                    format!("series number {i} with a rather long name to be cut"),
                    (0..20).map(|k| (k as f64, (k * i) as f64 - 30.0)).collect(),
                )
            })
            .collect();
        line_chart(
            &path,
            "Linear",
            &Axis::linear("k"),
            &Axis::linear("value"),
            &series,
            &[Threshold::new(100.0, "limit")],
        )
        .unwrap();
        assert!(check_png(&path) > 10_000);
    }

    #[test]
    fn charts_render_without_data() {
        let path = temp_png("empty_line.png");
        let empty = [
            Series::new("empty", vec![]),
            Series::new("all skipped", vec![(0.0, -1.0)]),
        ];
        line_chart(
            &path,
            "No data",
            &Axis::log("x"),
            &Axis::log("y"),
            &empty,
            &[],
        )
        .unwrap();
        check_png(&path);
        scatter_chart(
            &path,
            "No data",
            &Axis::log("x"),
            &Axis::linear("y"),
            &[],
            Some(&[]),
        )
        .unwrap();
        check_png(&path);
        bar_chart(&path, "No bars", &Axis::log("y"), &[]).unwrap();
        check_png(&path);
        bar_chart(
            &path,
            "Zero bar",
            &Axis::log("y"),
            &[("zero".to_string(), 0.0)],
        )
        .unwrap();
        check_png(&path);
        // A single point: degenerate ranges are widened.
        let one = [Series::new("one", vec![(3.0, 3.0)])];
        line_chart(&path, "One", &Axis::linear("x"), &Axis::log("y"), &one, &[]).unwrap();
        check_png(&path);
    }

    #[test]
    fn scatter_chart_with_front() {
        let path = temp_png("scatter.png");
        let series = vec![
            Series::new("f32", vec![(1.2, 4.5e-7), (0.9, 2e-6), (2.5, 1e-7)]),
            Series::new("f16 instances", vec![(0.6, 3e-4), (0.7, 1e-4), (0.0, 1e-3)]),
        ];
        let front = [(2.5, 1e-7), (0.6, 3e-4), (1.2, 4.5e-7), (0.7, 1e-4)];
        scatter_chart(
            &path,
            "Time versus error",
            &Axis::log("GPU time per frame (ms)"),
            &Axis::log("max relative depth error"),
            &series,
            Some(&front),
        )
        .unwrap();
        assert!(check_png(&path) > 5_000);
    }

    #[test]
    fn bar_chart_linear_and_log() {
        let path = temp_png("bars.png");
        let bars: Vec<(String, f64)> = vec![
            ("sphere".into(), 1.3e-7),
            ("rotated".into(), 2.5e-7),
            ("random 300".into(), 3.4e-7),
            ("ortho".into(), -4.5e-7),
        ];
        bar_chart(
            &path,
            "Depth error p99",
            &Axis::linear("relative error"),
            &bars,
        )
        .unwrap();
        assert!(check_png(&path) > 5_000);
        let bars: Vec<(String, f64)> = vec![
            ("tiny".into(), 1e-12),
            ("zero".into(), 0.0),
            ("huge".into(), 1e7),
            ("nan".into(), f64::NAN),
        ];
        bar_chart(&path, "Log bars", &Axis::log("value"), &bars).unwrap();
        assert!(check_png(&path) > 5_000);
    }

    #[test]
    fn bad_output_path_is_an_error() {
        let path = temp_png("no/such/dir/chart.png");
        let err = bar_chart(&path, "x", &Axis::linear("y"), &[("a".into(), 1.0)]).unwrap_err();
        assert!(err.to_string().contains("chart.png"), "{err}");
    }

    #[test]
    fn missing_font_names_file_and_fix() {
        let missing = Path::new("/nonexistent/fonts/DejaVuSans.ttf");
        let reason = read_font(missing, false).unwrap_err();
        assert!(
            reason.contains("/nonexistent/fonts/DejaVuSans.ttf"),
            "{reason}"
        );
        assert!(
            reason.contains("apt-get install fonts-dejavu-core"),
            "{reason}"
        );
        let reason = read_font(missing, true).unwrap_err();
        assert!(reason.contains(FONT_ENV), "{reason}");
    }

    #[test]
    fn ticks() {
        let inside = |s: &Scale, v: &[f64]| v.iter().all(|&t| t >= s.lo && t <= s.hi);
        // Nineteen decades: plotters labels every k-th power of ten, at most N_LABELS.
        let s = Scale::fit([1e-12, 1e7].into_iter(), true, 0.0);
        let majors = s.majors(N_LABELS);
        assert!(majors.len() <= N_LABELS && majors.len() >= 5, "{majors:?}");
        assert!(inside(&s, &majors), "{majors:?}");
        for &m in &majors {
            let decade = m.log10().round();
            assert!(
                (m / 10f64.powf(decade) - 1.0).abs() < 1e-9,
                "{m} in {majors:?}"
            );
        }
        assert_eq!(s.label(1e-12), "1e-12");
        assert_eq!(s.label(1e6), "1e6");

        let s = Scale::fit([1.0, 1000.0].into_iter(), true, 0.0);
        let majors = s.majors(N_LABELS);
        for decade in [1.0, 10.0, 100.0, 1000.0] {
            assert!(
                majors.iter().any(|&m| (m / decade - 1.0).abs() < 1e-9),
                "{decade}: {majors:?}"
            );
        }
        assert_eq!(s.label(100.0), "100");
        // The log axis puts each decade the same distance apart: 10 halfway from 1 to 100.
        let s = Scale::fit([1.0, 100.0].into_iter(), true, 0.0);
        assert_eq!(s.map(&10.0, (0, 1000)), 500);
        assert_eq!(s.map(&1.0, (0, 1000)), 0);

        // Less than a decade still gets labels.
        let s = Scale::fit([3.0, 5.0].into_iter(), true, 0.0);
        let majors = s.majors(N_LABELS);
        assert!(majors.len() >= 2 && inside(&s, &majors), "{majors:?}");

        let s = Scale::fit([0.0, 1.0].into_iter(), false, 0.0);
        let majors = s.majors(N_LABELS);
        assert!(majors.len() >= 2 && majors.len() <= N_LABELS, "{majors:?}");
        assert!(inside(&s, &majors), "{majors:?}");
        assert_eq!(s.label(0.6000000000000001), "0.6");

        let s = Scale::fit([1e-7, 5e-7].into_iter(), false, 0.0);
        assert_eq!(s.label(1.5e-7), "1.5e-7");

        let s = Scale::fit([1_000_000.0, 1_000_010.0].into_iter(), false, 0.0);
        let labels: Vec<String> = s.majors(N_LABELS).iter().map(|&v| s.label(v)).collect();
        assert!(labels.windows(2).all(|w| w[0] != w[1]), "{labels:?}");

        assert_eq!(fmt_value(0.25), "0.25");
        assert_eq!(fmt_value(3.4e-7), "3.4e-7");
    }
}

//! A minimal SVG writer for the report's log-log plots and stability maps, and the wet
//! timeline's linear plots.

use std::fmt::Write;

/// One line of a plot: a label, a colour, and (x, y) points (on a log plot, non-positive ones
/// are skipped).
pub struct Series {
    pub label: String,
    pub colour: &'static str,
    pub points: Vec<(f64, f64)>,
}

/// Colours for successive series.
pub const COLOURS: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#17becf", "#e377c2",
];

fn decades(lo: f64, hi: f64) -> (f64, f64) {
    (lo.log10().floor(), hi.log10().ceil().max(lo.log10().floor() + 1.0))
}

/// Where a plot goes and what it says.
pub struct Panel<'a> {
    pub ox: f64,
    pub oy: f64,
    pub w: f64,
    pub h: f64,
    pub title: &'a str,
    pub xl: &'a str,
    pub yl: &'a str,
}

/// How an axis maps values: by decades, or linearly from zero (or the data's least value,
/// if negative) to a round top.
#[derive(Clone, Copy, PartialEq)]
enum Scale {
    Log,
    Linear,
}

/// The axis range (in the mapped unit: decades for a log axis) and its ticks (value, label).
fn axis(scale: Scale, lo: f64, hi: f64) -> ((f64, f64), Vec<(f64, String)>) {
    match scale {
        Scale::Log => {
            let (a, b) = decades(lo, hi);
            (
                (a, b),
                (a as i32..=b as i32)
                    .map(|d| (10f64.powi(d), format!("1e{d}")))
                    .collect(),
            )
        }
        Scale::Linear => {
            let (lo, hi) = (lo.min(0.0), hi.max(lo.min(0.0) + 1e-12));
            // A step of 1, 2 or 5 times a power of ten giving 4 to 10 ticks.
            let raw = (hi - lo) / 5.0;
            let p = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 5.0, 10.0]
                .iter()
                .map(|m| m * p)
                .find(|s| (hi - lo) / s <= 8.0)
                .unwrap_or(10.0 * p);
            let (a, b) = ((lo / step).floor() * step, (hi / step).ceil() * step);
            let n = ((b - a) / step).round() as i32;
            (
                (a, b),
                (0..=n)
                    .map(|k| a + k as f64 * step)
                    .map(|v| (v, format!("{}", (v * 1e6).round() / 1e6)))
                    .collect(),
            )
        }
    }
}

/// A log-log plot of `series` in `panel`.
pub fn loglog(out: &mut String, panel: &Panel, series: &[Series]) {
    plot(out, panel, series, Scale::Log);
}

/// A plot of `series` in `panel` with linear axes.
#[allow(dead_code)] // used by examples/wet_timeline, not by the report
pub fn linear(out: &mut String, panel: &Panel, series: &[Series]) {
    plot(out, panel, series, Scale::Linear);
}

fn plot(out: &mut String, panel: &Panel, series: &[Series], scale: Scale) {
    let Panel {
        ox,
        oy,
        w,
        h,
        title,
        xl,
        yl,
    } = *panel;
    let shown =
        |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && (scale == Scale::Linear || (p.0 > 0.0 && p.1 > 0.0));
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(shown)
        .collect();
    if pts.is_empty() {
        return;
    }
    let min = |f: fn(&(f64, f64)) -> f64| pts.iter().map(f).fold(f64::INFINITY, f64::min);
    let max = |f: fn(&(f64, f64)) -> f64| pts.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
    let ((x0, x1), xticks) = axis(scale, min(|p| p.0), max(|p| p.0));
    let ((y0, y1), yticks) = axis(scale, min(|p| p.1), max(|p| p.1));
    let map = |v: f64| if scale == Scale::Log { v.log10() } else { v };
    let (l, r, t, b) = (ox + 60.0, ox + w - 10.0, oy + 30.0, oy + h - 45.0);
    let px = |x: f64| l + (map(x) - x0) / (x1 - x0) * (r - l);
    let py = |y: f64| b - (map(y) - y0) / (y1 - y0) * (b - t);
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" font-size="14" text-anchor="middle">{title}</text>"#,
        (l + r) / 2.0,
        oy + 18.0
    );
    let _ = writeln!(
        out,
        r##"<rect x="{l}" y="{t}" width="{}" height="{}" fill="none" stroke="#444"/>"##,
        r - l,
        b - t
    );
    for (v, label) in &xticks {
        let x = px(*v);
        let _ = writeln!(
            out,
            r##"<line x1="{x}" y1="{t}" x2="{x}" y2="{b}" stroke="#ddd"/><text x="{x}" y="{}" font-size="11" text-anchor="middle">{label}</text>"##,
            b + 14.0
        );
    }
    for (v, label) in &yticks {
        let y = py(*v);
        let _ = writeln!(
            out,
            r##"<line x1="{l}" y1="{y}" x2="{r}" y2="{y}" stroke="#ddd"/><text x="{}" y="{}" font-size="11" text-anchor="end">{label}</text>"##,
            l - 4.0,
            y + 4.0
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" font-size="12" text-anchor="middle">{xl}</text>"#,
        (l + r) / 2.0,
        b + 32.0
    );
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" font-size="12" text-anchor="middle" transform="rotate(-90 {} {})">{yl}</text>"#,
        ox + 14.0,
        (t + b) / 2.0,
        ox + 14.0,
        (t + b) / 2.0
    );
    for (k, s) in series.iter().enumerate() {
        let p: Vec<String> = s
            .points
            .iter()
            .filter(|p| shown(p))
            .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
            .collect();
        if !p.is_empty() {
            let _ = writeln!(
                out,
                r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="2"/>"#,
                p.join(" "),
                s.colour
            );
            for q in &p {
                let (cx, cy) = q.split_once(',').unwrap();
                let _ = writeln!(out, r#"<circle cx="{cx}" cy="{cy}" r="3" fill="{}"/>"#, s.colour);
            }
        }
        let ly = t + 14.0 + 16.0 * k as f64;
        let _ = writeln!(
            out,
            r#"<rect x="{}" y="{}" width="12" height="4" fill="{}"/><text x="{}" y="{}" font-size="11">{}</text>"#,
            r - 170.0,
            ly - 4.0,
            s.colour,
            r - 154.0,
            ly,
            s.label
        );
    }
}

/// Wraps panels into a standalone SVG document.
pub fn document(w: f64, h: f64, body: &str) -> String {
    format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\"><rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n{body}</svg>\n")
}

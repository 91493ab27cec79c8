//! A minimal SVG writer for the report's log-log plots and stability maps.

use std::fmt::Write;

/// One line of a log-log plot: a label, a colour, and (x, y) points (non-positive ones skipped).
pub struct Series {
    pub label: String,
    pub colour: &'static str,
    pub points: Vec<(f64, f64)>,
}

/// Colours for successive series.
pub const COLOURS: [&str; 6] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];

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

/// A log-log plot of `series` in `panel`.
pub fn loglog(out: &mut String, panel: &Panel, series: &[Series]) {
    let Panel {
        ox,
        oy,
        w,
        h,
        title,
        xl,
        yl,
    } = *panel;
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(|p| p.0 > 0.0 && p.1 > 0.0)
        .collect();
    if pts.is_empty() {
        return;
    }
    let (x0, x1) = decades(
        pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min),
        pts.iter().map(|p| p.0).fold(0.0, f64::max),
    );
    let (y0, y1) = decades(
        pts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
        pts.iter().map(|p| p.1).fold(0.0, f64::max),
    );
    let (l, r, t, b) = (ox + 60.0, ox + w - 10.0, oy + 30.0, oy + h - 45.0);
    let px = |x: f64| l + (x.log10() - x0) / (x1 - x0) * (r - l);
    let py = |y: f64| b - (y.log10() - y0) / (y1 - y0) * (b - t);
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
    for d in x0 as i32..=x1 as i32 {
        let x = px(10f64.powi(d));
        let _ = writeln!(
            out,
            r##"<line x1="{x}" y1="{t}" x2="{x}" y2="{b}" stroke="#ddd"/><text x="{x}" y="{}" font-size="11" text-anchor="middle">1e{d}</text>"##,
            b + 14.0
        );
    }
    for d in y0 as i32..=y1 as i32 {
        let y = py(10f64.powi(d));
        let _ = writeln!(
            out,
            r##"<line x1="{l}" y1="{y}" x2="{r}" y2="{y}" stroke="#ddd"/><text x="{}" y="{}" font-size="11" text-anchor="end">1e{d}</text>"##,
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
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
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

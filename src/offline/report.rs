//! `replay --report FILE`: an experiment's answers as one self-contained page: a chart (SVG) of
//! decisions by condition, the counts, the agreement between conditions, and the lines whose
//! decisions differ. Well-formed XHTML, so any XML parser reads it.
//!
//! Must not: load anything (no script, font or style sheet from elsewhere), or vary with
//! anything but its input: the same answers make the same bytes.

use std::fmt::Write;

use super::compare::{Comparison, percent};
use super::replay::Summary;
use crate::engine::input::escape_unseen;

/// Bar colours, one per condition in order (cycled past eight): distinguishable in print and
/// by most colour-blind readers (Tableau 10).
const PALETTE: [&str; 8] = [
    "#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948", "#b07aa1", "#ff9da7",
];

/// The chart's frame, in SVG user units (CSS pixels at 1:1).
const WIDTH: f64 = 760.0;
const HEIGHT: f64 = 340.0;
const LEFT: f64 = 56.0;
const RIGHT: f64 = 16.0;
const TOP: f64 = 40.0;
const BOTTOM: f64 = 48.0;

const STYLE: &str = "body{font:15px/1.45 system-ui,sans-serif;margin:2rem auto;max-width:60rem;padding:0 1rem;color:#222}\
h1{font-size:1.4rem}h2{font-size:1.1rem;margin-top:2rem}\
table{border-collapse:collapse;margin:.5rem 0}th,td{border:1px solid #ccc;padding:.25rem .5rem;vertical-align:top}\
th{background:#f3f3f3;text-align:left}td.n{text-align:right;font-variant-numeric:tabular-nums}\
.kind{font-weight:600}.none{color:#666}svg text{font:12px system-ui,sans-serif;fill:#222}";

/// Text for an element or an attribute: characters a terminal or a parser would act on shown
/// escaped (`\u{1b}`), then the five XML specials as entities.
fn text(raw: &str) -> String {
    let seen = escape_unseen(raw);
    let mut out = String::with_capacity(seen.len());
    for c in seen.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The page for a replay of `source` under `names` (the conditions, in order): `summary` of
/// every answer, `comparison` of the conditions' decisions.
pub fn report_html(source: &str, names: &[String], summary: &Summary, comparison: &Comparison) -> String {
    let kinds = summary.kinds();
    let mut page = String::new();
    let title = format!("Replay of {}", text(source));
    // `write!` to a String cannot fail.
    let _ = write!(
        page,
        "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"/>\n<title>{title}</title>\n\
         <style>{STYLE}</style>\n</head>\n<body>\n<h1>{title}</h1>\n"
    );
    let listed: Vec<String> = names.iter().map(|n| text(n)).collect();
    let errors = summary.errors.len();
    let _ = writeln!(
        page,
        "<p id=\"totals\" data-lines=\"{lines}\" data-answers=\"{total}\" data-errors=\"{errors}\">{lines} lines under \
         {count} conditions ({list}): {total} answers, {decided} decided, {errors} {noun}.</p>",
        lines = comparison.lines,
        total = summary.total,
        count = names.len(),
        list = listed.join(", "),
        decided = summary.total - errors,
        noun = if errors == 1 { "error" } else { "errors" },
    );

    page.push_str("<h2>Decisions by condition</h2>\n");
    page.push_str(&chart(names, &kinds, summary));
    page.push_str("<table id=\"decisions\">\n<tr><th>condition</th>");
    for kind in &kinds {
        let _ = write!(page, "<th>{}</th>", text(kind));
    }
    page.push_str("</tr>\n");
    for name in names {
        let _ = write!(page, "<tr><th>{}</th>", text(name));
        for kind in &kinds {
            let _ = write!(
                page,
                "<td class=\"n\" data-condition=\"{}\" data-decision=\"{}\">{}</td>",
                text(name),
                text(kind),
                count(summary, name, kind)
            );
        }
        page.push_str("</tr>\n");
    }
    page.push_str("</table>\n");

    page.push_str("<h2>Agreement</h2>\n<table id=\"agreement\">\n<tr><th>conditions</th><th>same decision</th><th>of lines</th><th>share</th></tr>\n");
    for ((i, j), agreed) in Comparison::pairs(names.len()).zip(&comparison.agreed) {
        let _ = writeln!(
            page,
            "<tr data-pair=\"{a} = {b}\"><td>{a} = {b}</td><td class=\"n\">{agreed}</td><td class=\"n\">{lines}</td><td class=\"n\">{share}</td></tr>",
            a = text(&names[i]),
            b = text(&names[j]),
            lines = comparison.lines,
            share = percent(*agreed, comparison.lines),
        );
    }
    page.push_str("</table>\n");

    let _ = writeln!(
        page,
        "<h2>Lines whose decisions differ ({})</h2>",
        comparison.differ.len()
    );
    if comparison.differ.is_empty() {
        page.push_str("<p class=\"none\">Every line got the same decision under every condition.</p>\n");
    } else {
        page.push_str("<table id=\"differ\">\n<tr><th>line</th><th>id</th>");
        for name in names {
            let _ = write!(page, "<th>{}</th>", text(name));
        }
        page.push_str("</tr>\n");
        for differs in &comparison.differ {
            let id = differs.id.as_deref().map(text).unwrap_or_default();
            let _ = write!(
                page,
                "<tr data-line=\"{line}\"><td class=\"n\">{line}</td><td>{id}</td>",
                line = differs.line
            );
            for (kind, words) in &differs.answers {
                let _ = write!(
                    page,
                    "<td data-decision=\"{k}\"><span class=\"kind\">{k}</span><br/>{w}</td>",
                    k = text(kind),
                    w = text(words)
                );
            }
            page.push_str("</tr>\n");
        }
        page.push_str("</table>\n");
    }
    page.push_str("</body>\n</html>\n");
    page
}

/// How many of condition `name`'s answers were of `kind`.
fn count(summary: &Summary, name: &str, kind: &str) -> usize {
    (summary.by_condition.get(name))
        .and_then(|kinds| kinds.get(kind))
        .copied()
        .unwrap_or(0)
}

/// A grouped bar chart: one group per decision kind, one bar per condition, counts above the
/// bars; y from 0 up, in whole steps.
fn chart(names: &[String], kinds: &[&str], summary: &Summary) -> String {
    let most = (names.iter())
        .flat_map(|n| kinds.iter().map(move |k| count(summary, n, k)))
        .max()
        .unwrap_or(0)
        .max(1);
    // Five steps or fewer, each a whole number of answers.
    let step = most.div_ceil(5).max(1);
    let top = step * most.div_ceil(step);
    let plot_w = WIDTH - LEFT - RIGHT;
    let plot_h = HEIGHT - TOP - BOTTOM;
    let y = |value: usize| TOP + plot_h * (1.0 - value as f64 / top as f64);
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        "<svg id=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{HEIGHT}\" viewBox=\"0 0 {WIDTH} {HEIGHT}\" role=\"img\" aria-label=\"Decisions by condition\">"
    );
    for tick in (0..=top).step_by(step) {
        let at = y(tick);
        let _ = writeln!(
            svg,
            "<line x1=\"{LEFT}\" x2=\"{:.1}\" y1=\"{at:.1}\" y2=\"{at:.1}\" stroke=\"#ddd\"/><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{tick}</text>",
            WIDTH - RIGHT,
            LEFT - 6.0,
            at + 4.0
        );
    }
    let group = plot_w / kinds.len().max(1) as f64;
    let bar = group * 0.8 / names.len().max(1) as f64;
    for (g, kind) in kinds.iter().enumerate() {
        let left = LEFT + group * g as f64 + group * 0.1;
        for (c, name) in names.iter().enumerate() {
            let value = count(summary, name, kind);
            let (x, top_y) = (left + bar * c as f64, y(value));
            let _ = writeln!(
                svg,
                "<rect x=\"{x:.1}\" y=\"{top_y:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"{}\" data-condition=\"{}\" data-decision=\"{}\" data-count=\"{value}\"><title>{}: {} {value}</title></rect>\
                 <text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{value}</text>",
                (bar - 2.0).max(1.0),
                TOP + plot_h - top_y,
                PALETTE[c % PALETTE.len()],
                text(name),
                text(kind),
                text(name),
                text(kind),
                x + bar / 2.0 - 1.0,
                top_y - 4.0
            );
        }
        let _ = writeln!(
            svg,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            left + group * 0.4,
            HEIGHT - BOTTOM + 18.0,
            text(kind)
        );
    }
    let _ = writeln!(
        svg,
        "<line x1=\"{LEFT}\" x2=\"{:.1}\" y1=\"{:.1}\" y2=\"{:.1}\" stroke=\"#888\"/>",
        WIDTH - RIGHT,
        TOP + plot_h,
        TOP + plot_h
    );
    // The legend, along the top.
    let mut x = LEFT;
    for (c, name) in names.iter().enumerate() {
        let _ = writeln!(
            svg,
            "<rect x=\"{x:.1}\" y=\"12\" width=\"12\" height=\"12\" fill=\"{}\"/><text x=\"{:.1}\" y=\"22\">{}</text>",
            PALETTE[c % PALETTE.len()],
            x + 16.0,
            text(name)
        );
        x += 24.0 + 7.5 * name.chars().count() as f64;
    }
    svg.push_str("</svg>\n");
    svg
}

//! The report's page, `index.html`: static and self-contained (inline CSS, no script, nothing
//! fetched from the network), with a summary, the three plots of [`super::plot`], the results
//! table with the Pareto front marked, and a gallery of every variant beside its error heat
//! map. All text is HTML-escaped and file names are percent-encoded as relative URLs.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::plot::{
    format_number, EFFECT_COSTS, ERROR_VS_TIME, ESTIMATE_VS_ERROR, HEIGHT, RAYS_VS_ERROR, WIDTH,
};
use super::{Point, Report};
use crate::film::{write_atomically, OutputError};

/// Width of a gallery thumbnail in CSS pixels (heat maps are shown at the same size).
const THUMB_WIDTH: u32 = 240;

/// Writes `dir/index.html` atomically and returns its path.
///
/// # Examples
/// ```no_run
/// # fn demo(report: &penumbra::report::Report) -> Result<(), penumbra::film::OutputError> {
/// let page = penumbra::report::html::write_index(report, std::path::Path::new("out"))?;
/// assert!(page.ends_with("index.html"));
/// # Ok(()) }
/// ```
pub fn write_index(report: &Report, dir: &Path) -> Result<PathBuf, OutputError> {
    let path = dir.join("index.html");
    write_atomically(&path, render_index(report).as_bytes())?;
    Ok(path)
}

/// The text of `index.html` for `report`.
pub fn render_index(report: &Report) -> String {
    let mut page = String::with_capacity(16 * 1024 + 1024 * report.points.len());
    let title = format!("Accuracy vs time — {}", report.scene);
    // Writing to a String cannot fail, hence the ignored results below.
    let _ = write!(
        page,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<main>\n<h1>{}</h1>\n",
        escape(&title),
        escape(&title)
    );
    summary(&mut page, report);
    plots(&mut page);
    table(&mut page, report);
    savings_table(&mut page, report);
    gallery(&mut page, report);
    let _ = write!(
        page,
        "</main>\n<footer>Made by penumbra {}.</footer>\n</body>\n</html>\n",
        escape(env!("CARGO_PKG_VERSION"))
    );
    page
}

/// Escapes `text` for HTML text and double- or single-quoted attribute values.
pub(crate) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
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

/// A file name relative to the report folder as an escaped relative URL: bytes other than
/// letters, digits, `-._~/` are percent-encoded (so no `:` can start a scheme), and a leading
/// `/` gets a `.` before it (so `//host` cannot name a server).
fn href(name: &str) -> String {
    let mut url = String::with_capacity(name.len() + 1);
    if name.starts_with('/') {
        url.push('.');
    }
    for b in name.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            url.push(char::from(b));
        } else {
            let _ = write!(url, "%{b:02X}");
        }
    }
    escape(&url)
}

/// Seconds with three significant digits (whole seconds from 1000 up).
fn seconds(v: f64) -> String {
    if v.is_finite() && v >= 999.5 {
        format!("{v:.0}")
    } else {
        format_number(v)
    }
}

/// An integer with narrow no-break spaces between groups of three digits.
fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() * 2);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push('\u{202F}');
        }
        out.push(c);
    }
    out
}

/// PSNR in dB, "∞" for an image equal to the reference.
fn psnr(v: f64) -> String {
    match v {
        v if v.is_nan() => "–".into(),
        v if v == f64::INFINITY => "∞".into(),
        v => format!("{v:.2}"),
    }
}

/// The non-zero ray kinds, for a tooltip.
fn ray_kinds(p: &Point) -> String {
    let kinds: Vec<String> =
        p.rays.kinds().iter().filter(|(_, n)| *n > 0).map(|(k, n)| format!("{k} {}", grouped(*n))).collect();
    kinds.join(" · ")
}

fn summary(page: &mut String, r: &Report) {
    let reference_time = if r.reference.seconds > 0.0 {
        format!("{} s, {} rays", seconds(r.reference.seconds), grouped(r.reference.rays.total()))
    } else {
        "read from a file".into()
    };
    let front = r.pareto_front().len();
    let axes = r.axes();
    let rows = [
        ("Scene", escape(&r.scene)),
        ("Posed by", escape(r.script.as_deref().unwrap_or("nothing (the scene as loaded)"))),
        ("Image", format!("{} × {} px", r.width, r.height)),
        ("Threads", r.threads.to_string()),
        ("SIMD", r.simd.name().to_owned()),
        ("Reference", format!("{} ({})", escape(&r.reference.description), escape(&reference_time))),
        (
            "Variants",
            format!(
                "{} over {} sweep axes ({}); {front} on the Pareto front",
                r.points.len(),
                axes.len(),
                escape(&axes.join(", "))
            ),
        ),
    ];
    page.push_str("<dl class=\"summary\">\n");
    for (term, value) in rows {
        let _ = writeln!(page, "<dt>{term}</dt><dd>{value}</dd>");
    }
    page.push_str("</dl>\n");
}

fn plots(page: &mut String) {
    page.push_str("<section id=\"plots\">\n<h2>Plots</h2>\n<div class=\"plots\">\n");
    let plots = [
        (ERROR_VS_TIME, "RMSE against median render time, log-log, with the Pareto front dashed."),
        (RAYS_VS_ERROR, "RMSE against rays traced, log-log."),
        (EFFECT_COSTS, "Median render time of each effect with the scene's setting and with one sample."),
        (
            ESTIMATE_VS_ERROR,
            "The noise-driven mode's estimated RMSE against its true RMSE, log-log; on the dashed line they are equal.",
        ),
    ];
    for (stem, caption) in plots {
        let _ = writeln!(
            page,
            "<figure><picture><source type=\"image/svg+xml\" srcset=\"{svg}\">\
             <img src=\"{png}\" width=\"{WIDTH}\" height=\"{HEIGHT}\" alt=\"{alt}\"></picture>\
             <figcaption>{alt}</figcaption></figure>",
            svg = href(&format!("{stem}.svg")),
            png = href(&format!("{stem}.png")),
            alt = escape(caption),
        );
    }
    page.push_str("</div>\n</section>\n");
}

fn table(page: &mut String, r: &Report) {
    let front = r.pareto_front();
    page.push_str(
        "<section id=\"results\">\n<h2>Results</h2>\n<div class=\"scroll\"><table>\n<thead><tr>\
         <th title=\"on the Pareto front\">★</th><th>Axis</th><th>Variant</th><th>Parameters</th>\
         <th class=\"num\">Median time (s)</th><th class=\"num\">Runs</th><th class=\"num\">Rays</th>\
         <th class=\"num\">RMSE</th><th class=\"num\">PSNR (dB)</th><th class=\"num\">SSIM</th>\
         </tr></thead>\n<tbody>\n",
    );
    for (i, p) in r.points.iter().enumerate() {
        let on_front = front.contains(&i);
        let params: Vec<String> =
            p.params.iter().map(|(k, v)| format!("{}={}", escape(k), escape(v))).collect();
        let _ = writeln!(
            page,
            "<tr{class}><td class=\"front\"{tip}>{star}</td><td>{axis}</td><td>{label}</td><td>{params}</td>\
             <td class=\"num\" title=\"{times}\">{secs}</td><td class=\"num\">{runs}</td>\
             <td class=\"num\" title=\"{kinds}\">{rays}</td><td class=\"num\">{rmse}</td>\
             <td class=\"num\">{psnr}</td><td class=\"num\">{ssim:.4}</td></tr>",
            class = if on_front { " class=\"pareto\"" } else { "" },
            tip = if on_front { " title=\"on the Pareto front\"" } else { "" },
            star = if on_front { "★" } else { "" },
            axis = escape(&p.axis),
            label = escape(&p.label),
            params = params.join(", "),
            secs = seconds(p.seconds),
            times = escape(&p.times.iter().map(|&t| seconds(t)).collect::<Vec<_>>().join(", ")),
            runs = p.runs,
            kinds = escape(&ray_kinds(p)),
            rays = grouped(p.rays.total()),
            rmse = format_number(p.rmse),
            psnr = psnr(p.psnr),
            ssim = p.ssim,
        );
    }
    page.push_str(
        "</tbody>\n</table></div>\n<p class=\"note\">★ on the Pareto front of time and RMSE: no other \
         variant is both faster and more accurate. Times are medians over interleaved rounds (every \
         configuration once per round); rows with equal settings share one render. Hover a time for \
         every round's, a ray count for its kinds.</p>\n</section>\n",
    );
}

/// The equal-error table: each adaptive point against the best fixed pattern at its RMSE.
fn savings_table(page: &mut String, r: &Report) {
    let savings = r.savings();
    if savings.is_empty() {
        return;
    }
    page.push_str(
        "<section id=\"savings\">\n<h2>Equal-error savings</h2>\n<div class=\"scroll\"><table>\n<thead><tr>\
         <th>Variant</th><th class=\"num\">RMSE</th><th class=\"num\">Rays</th><th class=\"num\">Median time (s)</th>\
         <th>Fixed, fewest rays</th><th class=\"num\">Its rays</th><th class=\"num\">× rays</th>\
         <th>Fixed, least time</th><th class=\"num\">Its time (s)</th><th class=\"num\">× time</th>\
         </tr></thead>\n<tbody>\n",
    );
    let cells = |f: &Option<crate::report::FixedAt>, value: &dyn Fn(f64) -> String| match f {
        Some(f) => format!(
            "<td>aa {}</td><td class=\"num\">{}</td><td class=\"num\">{:.2}</td>",
            escape(&f.pattern),
            value(f.value),
            f.ratio
        ),
        None => "<td colspan=\"3\">outside every fixed curve</td>".to_owned(),
    };
    for s in &savings {
        let _ = writeln!(
            page,
            "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>{}{}</tr>",
            escape(&s.label),
            format_number(s.rmse),
            grouped(s.rays),
            seconds(s.seconds),
            cells(&s.fixed_rays, &|v| grouped(v.round() as u64)),
            cells(&s.fixed_seconds, &seconds),
        );
    }
    page.push_str(
        "</tbody>\n</table></div>\n<p class=\"note\">What the best fixed AA pattern needs for each adaptive \
         variant's RMSE, read log-log between the two AA points around it; × is that over the variant's own \
         (above 1: the variant saves).</p>\n</section>\n",
    );
}

/// An `<img>` of `name` at thumbnail size, or a placeholder when there is no file.
fn thumbnail(name: &str, alt: &str, width: u32, height: u32) -> String {
    if name.is_empty() {
        return format!(
            "<span class=\"missing\" style=\"width:{width}px;height:{height}px\">no image</span>"
        );
    }
    format!(
        "<img src=\"{}\" loading=\"lazy\" width=\"{width}\" height=\"{height}\" alt=\"{}\">",
        href(name),
        escape(alt)
    )
}

fn gallery(page: &mut String, r: &Report) {
    let width = THUMB_WIDTH.min(r.width.max(1));
    let height = (f64::from(width) * f64::from(r.height) / f64::from(r.width.max(1))).round().max(1.0) as u32;
    let front = r.pareto_front();
    let _ = writeln!(
        page,
        "<section id=\"gallery\">\n<h2>Gallery</h2>\n<div class=\"gallery\" style=\"--thumb: {width}px\">"
    );
    let _ = writeln!(
        page,
        "<figure class=\"reference\"><div class=\"pair\">{}</div><figcaption><b>Reference</b> — {}</figcaption></figure>",
        thumbnail(&r.reference.image, "reference image", width, height),
        escape(&r.reference.description)
    );
    for (i, p) in r.points.iter().enumerate() {
        let mark = if front.contains(&i) { " <span title=\"on the Pareto front\">★</span>" } else { "" };
        let _ = writeln!(
            page,
            "<figure><div class=\"pair\">{}{}</div><figcaption><b>{}</b>{mark} — RMSE {}</figcaption></figure>",
            thumbnail(&p.image, &format!("{} render", p.label), width, height),
            thumbnail(&p.heatmap, &format!("{} error heat map", p.label), width, height),
            escape(&p.label),
            format_number(p.rmse)
        );
    }
    page.push_str(
        "</div>\n<p class=\"note\">Each variant beside its error heat map against the reference.</p>\n</section>\n",
    );
}

/// The page's inline style sheet (system fonts only).
const STYLE: &str = "
:root { color-scheme: light; --ink: #222; --muted: #666; --rule: #ddd; --accent: #0072b2; --front: #fff6d6; }
* { box-sizing: border-box; }
body { margin: 0; color: var(--ink); background: #fafafa;
  font: 15px/1.45 system-ui, -apple-system, 'Segoe UI', Roboto, 'Helvetica Neue', Arial, sans-serif; }
main { max-width: 1700px; margin: 0 auto; padding: 24px 28px 8px; }
h1 { font-size: 1.6em; margin: 0 0 12px; font-weight: 600; }
h2 { font-size: 1.2em; margin: 32px 0 12px; padding-bottom: 4px; border-bottom: 1px solid var(--rule); font-weight: 600; }
dl.summary { display: grid; grid-template-columns: max-content 1fr; gap: 4px 18px; margin: 0; }
dl.summary dt { color: var(--muted); }
dl.summary dd { margin: 0; }
.plots { display: flex; flex-wrap: wrap; gap: 16px; }
figure { margin: 0; }
.plots figure { flex: 1 1 560px; max-width: 818px; min-width: 0; background: #fff; border: 1px solid var(--rule); padding: 8px; }
.plots img { display: block; width: 100%; height: auto; }
figcaption { color: var(--muted); font-size: 0.9em; margin-top: 4px; }
.scroll { overflow-x: auto; }
table { border-collapse: collapse; background: #fff; border: 1px solid var(--rule); font-size: 0.92em; }
th, td { padding: 5px 10px; border-bottom: 1px solid #eee; text-align: left; white-space: nowrap; }
th { background: #f0f0f0; font-weight: 600; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; }
tr.pareto { background: var(--front); }
td.front { color: #b8860b; text-align: center; }
.note { color: var(--muted); font-size: 0.88em; }
.gallery { display: grid; gap: 16px;
  grid-template-columns: repeat(auto-fill, min(100%, calc(2 * var(--thumb) + 26px))); }
.gallery figure { background: #fff; border: 1px solid var(--rule); padding: 8px; }
.pair { display: flex; gap: 8px; }
.pair img { max-width: 50%; height: auto; background: #eee; }
.reference .pair img { max-width: 100%; }
.missing { display: inline-flex; align-items: center; justify-content: center; color: var(--muted); background: #eee; }
footer { max-width: 1700px; margin: 0 auto; padding: 12px 28px 24px; color: var(--muted); font-size: 0.85em; }
";

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::plot::tests::{degenerate_report, synthetic_report};

    #[test]
    fn escape_handles_markup_characters() {
        assert_eq!(escape(r#"<a href="x">&'</a>"#), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;&lt;/a&gt;");
        assert_eq!(escape("plain — ∞"), "plain — ∞");
        assert_eq!(escape(""), "");
    }

    #[test]
    fn file_names_become_relative_urls() {
        assert_eq!(href("aa_16.png"), "aa_16.png");
        assert_eq!(href("dir/a b#1?.png"), "dir/a%20b%231%3F.png");
        assert_eq!(href("javascript:x"), "javascript%3Ax");
        assert_eq!(href("//host/x.png"), ".//host/x.png");
        assert_eq!(href("a&b\".png"), "a%26b%22.png");
        assert_eq!(href("é.png"), "%C3%A9.png");
    }

    #[test]
    fn numbers_in_the_table_are_readable() {
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1_228_800), "1\u{202F}228\u{202F}800");
        assert_eq!(psnr(f64::INFINITY), "∞");
        assert_eq!(psnr(31.256), "31.26");
        assert_eq!(seconds(41.5), "41.5");
        assert_eq!(seconds(1234.4), "1234");
    }

    #[test]
    fn the_index_links_every_image_and_marks_the_front() {
        let dir = tempfile::tempdir().unwrap();
        let report = synthetic_report();
        let path = write_index(&report, dir.path()).unwrap();
        assert_eq!(path, dir.path().join("index.html"));
        let html = std::fs::read_to_string(&path).unwrap();

        assert!(html.starts_with("<!DOCTYPE html>"));
        assert!(html.trim_end().ends_with("</html>"));
        for stem in [ERROR_VS_TIME, RAYS_VS_ERROR, EFFECT_COSTS, ESTIMATE_VS_ERROR] {
            assert!(html.contains(&format!("\"{stem}.svg\"")), "{stem}.svg");
            assert!(html.contains(&format!("\"{stem}.png\"")), "{stem}.png");
        }
        assert!(html.contains("\"reference.png\""));
        for p in &report.points {
            assert!(html.contains(&format!("src=\"{}\" loading=\"lazy\"", p.image)), "{}", p.image);
            assert!(html.contains(&format!("src=\"{}\" loading=\"lazy\"", p.heatmap)), "{}", p.heatmap);
            assert!(html.contains(&format!("<td>{}</td>", p.label)), "{}", p.label);
        }

        // Text is escaped, nothing is fetched, nothing runs.
        assert!(html.contains("scenes/cornell &lt;glossy&gt; &amp; &quot;lens&quot;.ron"));
        assert!(!html.contains("<glossy>"));
        assert!(!html.contains("http://") && !html.contains("https://"));
        assert!(!html.contains("<script") && !html.contains("<link"));

        // PSNR of the point equal to the reference, and the Pareto rows.
        assert!(html.contains("<td class=\"num\">∞</td>"));
        let front = report.pareto_front();
        assert_eq!(html.matches("<tr class=\"pareto\">").count(), front.len());
        for (i, p) in report.points.iter().enumerate() {
            let row = html.lines().find(|l| l.contains(&format!("<td>{}</td>", p.label))).unwrap();
            assert_eq!(row.starts_with("<tr class=\"pareto\">"), front.contains(&i), "{row}");
        }
    }

    #[test]
    fn a_degenerate_report_still_renders() {
        let dir = tempfile::tempdir().unwrap();
        let mut report = degenerate_report();
        report.reference.image.clear();
        report.width = 0;
        let html = std::fs::read_to_string(write_index(&report, dir.path()).unwrap()).unwrap();
        assert!(html.contains("<td>aa 1</td>"));
        assert!(html.contains("no image"));
        assert_eq!(html.matches("<tr class=\"pareto\">").count(), 1);
    }

    /// A tool, not a test: writes the page and plots of the synthetic report for a person to look at,
    /// into `$PENUMBRA_PLOT_DIR` (default `target/inspect`). Run it with
    /// `cargo test --release --lib a_page_can_be_written_for_inspection -- --ignored`.
    #[test]
    #[ignore = "writes files for inspection; asserts nothing"]
    fn a_page_can_be_written_for_inspection() {
        let dir = std::env::var_os("PENUMBRA_PLOT_DIR")
            .map_or_else(|| PathBuf::from("target/inspect"), PathBuf::from);
        std::fs::create_dir_all(&dir).unwrap();
        write_index(&synthetic_report(), &dir).unwrap();
    }
}

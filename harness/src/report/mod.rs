//! What a validation run writes for people: `index.html` (self-contained: inline CSS and SVG,
//! no fonts, scripts from elsewhere or network) and `summary.md`.
//!
//! The HTML gives a summary (counts, the slowest cases, versions, corrections), then one
//! section per case: its provenance, a link to its file, every check with value, expected,
//! allowed range, tolerance and reason, margin and verdict, and the case's plots. Plots come
//! from the results alone (see [`figures`]); nothing is recomputed here.
//!
//! A small inline script checks the page once it has loaded: every figure must hold an SVG
//! with drawn marks, or the page marks itself `data-report-check="empty-plot"`. The
//! headless-browser check (`scripts/check-report`) reads that mark. With `?section=ID` in its
//! address the page hides what comes before that section, for screenshots of it (a headless
//! browser's screenshot does not follow a `#fragment`: it comes out blank).

pub mod figures;
pub mod fit;
pub mod generated;
pub mod junit;
pub mod plot;
pub mod quoted;
pub mod retune;
pub mod sensitivity;
pub mod snapshots;
pub mod tables;
pub mod uncertainty;

use crate::report::tables::Counts;
use crate::suite::outcome::{CheckResult, Outcome};
use crate::suite::validation::CaseRan;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One case as it ran, with the studies the report shows beside it.
#[derive(Debug, Clone)]
pub struct CaseRun {
    /// The case, its results, its time, the corrections it ran with and its scores, as the
    /// validation ran it.
    pub ran: CaseRan,
    /// The case's sensitivity study, if it asks for one (or why it could not be run).
    pub sensitivity: Option<Result<crate::fit::sensitivity::Study, String>>,
    /// The case's uncertainty (`validate --uncertainty`).
    pub uncertainty: Option<crate::uncertainty::propagate::CaseUncertainty>,
}

/// A whole validation run.
#[derive(Debug, Clone, Default)]
pub struct Run {
    pub cases: Vec<CaseRun>,
    /// Case files that did not load, rendered.
    pub input_errors: Vec<String>,
    /// Correction files given, with what they set.
    pub corrections: Vec<(PathBuf, String)>,
    pub seconds: f64,
    /// The data sets' scores, judged against the committed scoreboard.
    pub scores: Vec<crate::suite::review::Judged>,
    /// The committed versions of the scoreboard, oldest first (from git, where it is there).
    pub score_versions: Vec<crate::suite::scoreboard::Version>,
    /// The acceptance log's entries, oldest first (`reports/acceptances.yaml`).
    pub acceptances: Vec<crate::suite::review::Acceptance>,
}

impl Run {
    /// Every check's outcome, tallied.
    pub fn counts(&self) -> Counts {
        let mut all = Counts::default();
        for c in &self.cases {
            all.merge(&crate::report::tables::counts(&c.ran.results));
        }
        all
    }

    /// Every check's result, case by case.
    pub fn results(&self) -> Vec<CheckResult> {
        self.cases
            .iter()
            .flat_map(|c| c.ran.results.iter().cloned())
            .collect()
    }
}

/// The versions a report names.
pub fn versions() -> Vec<(&'static str, String)> {
    vec![
        ("cierva", env!("CARGO_PKG_VERSION").to_string()),
        ("model (cierva-model)", cierva_model::VERSION.to_string()),
        ("target", std::env::consts::ARCH.to_string()),
    ]
}

fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            _ => o.push(ch),
        }
    }
    o
}

/// A path relative to `from` (a directory), for links; both are made absolute first.
pub fn relative_link(target: &Path, from: &Path) -> String {
    let abs = |p: &Path| {
        std::fs::canonicalize(p).unwrap_or_else(|_| {
            std::env::current_dir()
                .map(|d| d.join(p))
                .unwrap_or_else(|_| p.to_path_buf())
        })
    };
    let (t, f) = (abs(target), abs(from));
    let tc: Vec<_> = t.components().collect();
    let fc: Vec<_> = f.components().collect();
    let common = tc.iter().zip(&fc).take_while(|(a, b)| a == b).count();
    let mut parts: Vec<String> = vec!["..".into(); fc.len() - common];
    parts.extend(
        tc[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    parts.join("/")
}

fn num(v: f64) -> String {
    if v.is_nan() {
        "NaN".into()
    } else if v.is_infinite() || v.abs() >= 1e5 {
        if v > 0.0 {
            "∞".into()
        } else {
            "−∞".into()
        }
    } else if v == 0.0 || (1e-3..1e4).contains(&v.abs()) {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.4e}")
    }
}

fn outcome_class(o: Outcome) -> &'static str {
    match o {
        Outcome::Pass => "pass",
        Outcome::Fail => "fail",
        Outcome::ExpectedFailure => "xfail",
        Outcome::DiscrepancyMoved | Outcome::UnexpectedPass | Outcome::Error => "xpass",
    }
}

const CSS: &str = r#"
.bars{display:inline-block;vertical-align:top;margin:6px 18px 6px 0;font-size:12px}.bar-row{display:flex;align-items:center;gap:6px}.bar-name{width:240px;text-align:right}.bar-track{position:relative;display:inline-block;width:160px;height:10px;background:#f4f4f6}.bar-total{position:absolute;left:0;top:0;height:10px;background:#1f5fa8}.bar-first{position:absolute;left:0;top:3px;height:4px;background:#9cc3ee}
body{font-family:system-ui,-apple-system,"Segoe UI",sans-serif;margin:0 auto;max-width:1180px;padding:0 18px 60px;color:#1d1d1f;line-height:1.4}
h1{margin:18px 0 4px}h2{margin-top:40px;border-bottom:2px solid #ddd;padding-bottom:4px}h3{margin:22px 0 6px}
table{border-collapse:collapse;margin:8px 0;font-size:13px}td,th{border:1px solid #ddd;padding:3px 7px;vertical-align:top}
th{background:#f4f4f6;text-align:left}td.n{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
.pass{color:#17692f}.fail{color:#b00020;font-weight:bold}.xfail{color:#8a5a00}.xpass{color:#b00020;font-weight:bold}
span.badge{display:inline-block;border-radius:9px;padding:0 8px;font-size:12px;border:1px solid currentColor}
.muted{color:#666;font-size:13px}.spark{vertical-align:middle}.hist{white-space:nowrap}.prov{background:#f8f8fa;border-left:3px solid #ccc;padding:6px 10px;font-size:13px}
.plots{display:flex;flex-wrap:wrap;gap:10px}figure.plot{margin:0;border:1px solid #e4e4e4;padding:4px}
figure.plot figcaption{font-size:12px;color:#555;max-width:460px}
nav ul{columns:2;font-size:13px}code{font-size:12px}.why{font-size:12px;color:#8a5a00}
"#;

const CHECK_SCRIPT: &str = r#"
window.addEventListener('error',function(e){document.body.dataset.reportCheck='error: '+e.message});
window.addEventListener('load',function(){
  if((document.body.dataset.reportCheck||'').indexOf('error')===0)return;
  var figs=document.querySelectorAll('figure.plot'),empty=[];
  figs.forEach(function(f){var s=f.querySelector('svg');
    var marks=s?s.querySelectorAll('circle,polyline,polygon,path,line,rect').length:0;
    var b=s?s.getBBox():{width:0,height:0};
    if(!s||marks<3||b.width<10||b.height<10||Number(f.dataset.points)<1)empty.push(f.id)});
  document.body.dataset.figures=String(figs.length);
  document.body.dataset.reportCheck=empty.length?('empty-plot: '+empty.join(' ')):'ok';
  // ?section=ID shows the page from that section on (what came before it hidden), so that a
  // headless browser's screenshot, which does not follow a #fragment, shows the section.
  var id=new URLSearchParams(location.search).get('section'),el=id&&document.getElementById(id);
  for(var n=el;n&&n!==document.body;n=n.parentElement){
    for(var p=n.previousElementSibling;p;p=p.previousElementSibling){
      if(p.tagName!=='SCRIPT')p.style.display='none'}}
});
"#;

/// The report as one HTML page; links to case files are relative to `dir`, where the page is
/// written.
pub fn html(run: &Run, dir: &Path) -> String {
    let counts = run.counts();
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width\">\
         <title>cierva validation report</title><style>{CSS}</style>\
         <script>{CHECK_SCRIPT}</script></head><body>\n"
    );
    let _ = writeln!(
        h,
        "<h1>cierva validation report</h1><p class=\"muted\">{}, {}, {:.1} s. \
         Validation against outside references, counted apart from cross-code, verification \
         and regression checks.</p>",
        crate::units::count(run.cases.len(), "case", "cases"),
        crate::units::count(counts.total(), "check", "checks"),
        run.seconds
    );
    h += &scoreboard_html(run);
    h += &acceptances_html(&run.acceptances);
    h += &uncertainty::html(run);
    h += &summary_html(run, &counts);
    let cross = figures::across_cases(run);
    if !cross.is_empty() {
        h += "<h2 id=\"derivatives-against-airspeed\">Derivatives against airspeed</h2>\
              <p class=\"muted\">Every aircraft derivative check, by aircraft and derivative: \
              the model at each mass as a line, the reference's allowed range as a bar \
              (seed 001 Fig. 5). A bar that runs off the frame is a one-sided (sign) check.</p>";
        h += &figures_html("all", &cross);
    }
    let inflow = figures::inflow_against_airspeed(run);
    if !inflow.is_empty() {
        h += "<h2 id=\"inflow-against-airspeed\">Inflow against airspeed</h2>\
              <p class=\"muted\">Inflow components recovered from blade flapping by seed 003's \
              method, every teeter record by rotor (seed 003 Figs. 4-6).</p>";
        h += &figures_html("inflow", &inflow);
    }
    h += &fits_html(dir);
    h += "<h2>Cases</h2><nav><ul>";
    for c in &run.cases {
        let k = crate::report::tables::counts(&c.ran.results);
        let _ = write!(
            h,
            "<li><a href=\"#case-{id}\">{id}</a> <span class=\"muted\">{} pass, {} xfail{}</span></li>",
            k.pass,
            k.expected_failure,
            Outcome::ALL
                .iter()
                .filter(|o| !o.ok() && k.of(**o) > 0)
                .map(|o| format!(", <span class=\"fail\">{} {}</span>", k.of(*o), o.label()))
                .collect::<String>(),
            id = esc(&c.ran.case.id)
        );
    }
    h += "</ul></nav>\n";
    for c in &run.cases {
        h += &case_html(c, dir);
    }
    h += "</body></html>\n";
    h
}

/// The fits `cierva fit` has reported into `dir/fits` (its default report folder): each
/// before/after figure inline, with a link to its Markdown report.
fn fits_html(dir: &Path) -> String {
    let Ok(entries) = std::fs::read_dir(dir.join("fits")) else {
        return String::new();
    };
    let mut svgs: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .collect();
    svgs.sort();
    let mut h = String::new();
    for p in svgs {
        let Ok(svg) = std::fs::read_to_string(&p) else {
            continue;
        };
        if !svg.starts_with("<svg") {
            continue;
        }
        let stem = p
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let md = format!("fits/{stem}.md");
        let _ = write!(
            h,
            "<figure class=\"plot\" id=\"fig-fit-{s}\" data-points=\"{n}\">{svg}<figcaption>fit \
             <code>{s}</code> (as last run by <code>cierva fit</code>): <a href=\"{md}\">its report</a></figcaption></figure>",
            s = esc(&stem),
            n = svg.matches("<circle").count(),
        );
    }
    if h.is_empty() {
        return h;
    }
    format!(
        "<h2 id=\"fits\">Fitted corrections, before and after</h2><p class=\"muted\">Each fit's \
         targets in their own standard errors, at the uncorrected start and fitted; the band is \
         95 %. Rerun a fit with <code>cierva fit FIT.yaml</code>.</p><div class=\"plots\">{h}</div>"
    )
}

/// The scoreboard: each data set's scores, committed and now, and their history over the
/// committed versions.
fn scoreboard_html(run: &Run) -> String {
    if run.scores.is_empty() {
        return String::new();
    }
    let mut h = String::from(
        "<h2 id=\"scoreboard\">Scoreboard</h2><p class=\"muted\">How well the model does \
         against each outside data set (the <code>scores</code> of its case; metrics in \
         <code>harness/src/suite/scoreboard.rs</code>). <code>cargo test</code> fails when a score gets \
         worse than committed in <code>reports/scoreboard.yaml</code> by more than its noise \
         floor; <code>cierva review --accept --reason TEXT</code> commits a new value and logs \
         why (below). History: the value at \
         each commit that changed the scoreboard, oldest first, then now (the ringed point; hover \
         a point for its commit), with the first and the present value.</p><table><tr><th>data set</th>\
         <th>score</th><th>metric</th><th>over</th><th>now</th><th>committed</th><th>change</th>\
         <th>history</th><th>what it measures</th></tr>",
    );
    for j in &run.scores {
        let s = &j.score;
        let committed: Vec<plot::Spark> =
            crate::suite::scoreboard::history(&s.case, &s.id, &run.score_versions)
                .into_iter()
                .map(|(date, commit, value)| plot::Spark {
                    label: format!("{commit} {date}"),
                    value,
                })
                .collect();
        let now = plot::Spark {
            label: "now".into(),
            value: s.value,
        };
        // The chart, then the first committed value and now's, as numbers.
        let hist =
            plot::sparkline_svg(&committed, &now).map_or(String::new(), |svg| {
                match committed.first() {
                    Some(first) => format!("{svg} {} → {}", num(first.value), num(s.value)),
                    None => format!("{svg} (not committed)"),
                }
            });
        let class = match j.change {
            crate::suite::scoreboard::Change::Worse | crate::suite::scoreboard::Change::New => {
                "fail"
            }
            crate::suite::scoreboard::Change::Better => "pass",
            crate::suite::scoreboard::Change::Same => "",
        };
        let _ = write!(
            h,
            "<tr><td><a href=\"#case-{c}\">{c}</a></td><td>{id}</td><td>{m}{q}</td>\
             <td class=\"n\">{n}</td><td class=\"n\">{now}</td><td class=\"n\">{then}</td>\
             <td class=\"{class}\">{change}</td><td class=\"muted hist\">{hist}</td>\
             <td class=\"muted\">{why}</td></tr>",
            c = esc(&s.case),
            id = esc(&s.id),
            m = s.metric.name(),
            q = s
                .quantity
                .as_ref()
                .map_or(String::new(), |q| format!(" of <code>{}</code>", esc(q))),
            n = s.count,
            now = num(s.value),
            then = j.committed.map_or("—".to_string(), num),
            change = j.change.label(),
            why = esc(&s.reason),
        );
    }
    h += "</table>";
    h
}

/// How many of the acceptance log's entries the report shows, newest first.
const ACCEPTANCES_SHOWN: usize = 10;

/// The acceptance log's last entries, newest first: when, on which commit, why, what changed.
fn acceptances_html(log: &[crate::suite::review::Acceptance]) -> String {
    if log.is_empty() {
        return String::new();
    }
    let mut h = format!(
        "<h2 id=\"acceptances\">Acceptances</h2><p class=\"muted\">The last {} of {} entries \
         of <code>reports/acceptances.yaml</code>, newest first: each <code>cierva review \
         --accept --reason TEXT</code>, with its reason and what it changed on the scoreboard and \
         in the discrepancy records. <code>cargo test</code> fails when the committed files are not what \
         the last entry accepted.</p><table><tr><th>date</th><th>commit</th><th>reason</th>\
         <th>changes</th></tr>",
        log.len().min(ACCEPTANCES_SHOWN),
        log.len()
    );
    for a in log.iter().rev().take(ACCEPTANCES_SHOWN) {
        let show =
            |v: &Option<crate::suite::review::Value>| v.as_ref().map_or("—".into(), |v| v.show());
        let changes = if a.changes.is_empty() {
            "none".to_string()
        } else {
            a.changes
                .iter()
                .map(|c| {
                    format!(
                        "{} {}: {} → {} ({})",
                        esc(&c.case),
                        esc(&c.item),
                        esc(&show(&c.old)),
                        esc(&show(&c.new)),
                        c.direction.name()
                    )
                })
                .collect::<Vec<_>>()
                .join("<br>")
        };
        let _ = write!(
            h,
            "<tr><td>{}</td><td><code>{}</code></td><td>{}</td><td class=\"muted\">{changes}</td></tr>",
            esc(&a.date),
            esc(&a.commit),
            esc(&a.reason)
        );
    }
    h += "</table>";
    h
}

fn summary_html(run: &Run, counts: &Counts) -> String {
    let mut h = String::from(
        "<h2 id=\"summary\">Summary</h2><p class=\"muted\">Checks by class: only \
         <b>validation</b> compares the model with measured data; <b>cross-code</b> compares it \
         with another model, <b>verification</b> with a known answer, <b>regression</b> with its \
         own earlier output.</p><table><tr><th>class</th><th>checks</th>",
    );
    for o in Outcome::ALL {
        let _ = write!(h, "<th>{}</th>", o.label());
    }
    h += "</tr>";
    let results = run.results();
    let mut rows = crate::report::tables::counts_by_class(&results);
    rows.push((crate::suite::case::CheckClass::Regression, *counts));
    let last = rows.len() - 1;
    for (i, (k, c)) in rows.iter().enumerate() {
        let _ = write!(
            h,
            "<tr><th>{}</th><td class=\"n\">{}</td>",
            if i == last { "all" } else { k.name() },
            c.total()
        );
        for o in Outcome::ALL {
            let n = c.of(o);
            let _ = write!(
                h,
                "<td class=\"n {}\">{n}</td>",
                if n > 0 { outcome_class(o) } else { "" }
            );
        }
        h += "</tr>";
    }
    let _ = write!(
        h,
        "</table><p>input errors (files that do not load, external models that fail): <span class=\"n {}\">{}</span></p>",
        if run.input_errors.is_empty() {
            ""
        } else {
            "fail"
        },
        run.input_errors.len()
    );
    let verdict = if !run.input_errors.is_empty() {
        ("fail", "bad input: exit code 2")
    } else if counts.failing() > 0 {
        (
            "fail",
            "a check failed unexpectedly, a known discrepancy moved, an expected failure passed \
             or a check could not be evaluated: exit code 1",
        )
    } else {
        (
            "pass",
            "every check passed or failed as its case expects: exit code 0",
        )
    };
    let _ = write!(h, "<p class=\"{}\">{}</p>", verdict.0, verdict.1);
    for e in &run.input_errors {
        let _ = write!(h, "<pre class=\"fail\">{}</pre>", esc(e));
    }
    let mut slow: Vec<&CaseRun> = run.cases.iter().collect();
    slow.sort_by(|a, b| b.ran.seconds.total_cmp(&a.ran.seconds));
    h += "<h3>Slowest cases</h3><p class=\"muted\">Time of each case's checks, summed over \
          the threads that ran them; a linearisation that several cases share is computed once, by the first case that needs \
          it.</p><table><tr><th>case</th><th>checks</th><th>time, s</th></tr>";
    for c in slow.iter().take(5) {
        let _ = write!(
            h,
            "<tr><td><a href=\"#case-{id}\">{id}</a></td><td class=\"n\">{}</td><td class=\"n\">{:.2}</td></tr>",
            c.ran.results.len(),
            c.ran.seconds,
            id = esc(&c.ran.case.id)
        );
    }
    h += "</table><h3>Versions and corrections</h3><table>";
    for (k, v) in versions() {
        let _ = write!(h, "<tr><th>{k}</th><td>{}</td></tr>", esc(&v));
    }
    if run.corrections.is_empty() {
        h += "<tr><th>corrections</th><td>none given (each case runs as its files say)</td></tr>";
    }
    for (p, d) in &run.corrections {
        let _ = write!(
            h,
            "<tr><th>corrections</th><td><code>{}</code>: {}</td></tr>",
            esc(&p.display().to_string()),
            esc(d)
        );
    }
    h += "</table>";
    h
}

fn figures_html(prefix: &str, figs: &[plot::Figure]) -> String {
    let mut h = String::from("<div class=\"plots\">");
    let mut i = 0;
    while i < figs.len() {
        // A figure alone, or the run of figures stacked under one caption on one abscissa.
        let n = match &figs[i].stack {
            Some(s) => figs[i..]
                .iter()
                .take_while(|f| f.stack.as_ref() == Some(s))
                .count(),
            None => 1,
        };
        let run = &figs[i..i + n];
        let (svg, caption) = match &figs[i].stack {
            Some(s) => (plot::panels_svg(run, 460, 230), s.as_str()),
            None => (run[0].svg(460, 320), run[0].title.as_str()),
        };
        if let Some(svg) = svg {
            let _ = write!(
                h,
                "<figure class=\"plot\" id=\"fig-{}-{i}\" data-points=\"{}\">{svg}<figcaption>{}</figcaption></figure>",
                esc(prefix),
                run.iter().map(plot::Figure::points).sum::<usize>(),
                esc(caption)
            );
        }
        i += n;
    }
    h += "</div>";
    h
}
/// What loading a case's records and trim points mapped, converted or did not compare, by file
/// (its path from the suite's root); empty where they were read as written.
fn data_as_read_html(case: &crate::suite::case::Case, dir: &Path) -> String {
    let mut read: Vec<(std::path::PathBuf, String)> = Vec::new();
    for k in &case.checks {
        for n in k.behaviour().input_notes() {
            if !read.contains(&n) {
                read.push(n);
            }
        }
    }
    if read.is_empty() {
        return String::new();
    }
    let items: Vec<String> = read
        .iter()
        .map(|(file, note)| {
            format!(
                "<li><code>{}</code>: {}</li>",
                esc(&relative_link(file, dir.parent().unwrap_or(dir))),
                esc(note)
            )
        })
        .collect();
    format!(
        "<div class=\"prov\"><b>Data as read.</b><ul>{}</ul></div>",
        items.concat()
    )
}

fn case_html(c: &CaseRun, dir: &Path) -> String {
    let case = &c.ran.case;
    let link = relative_link(&case.path, dir);
    let mut h = String::new();
    let _ = write!(
        h,
        "<section><h2 id=\"case-{id}\">{id}</h2><p>{title}</p>\
         <p class=\"muted\">file <a href=\"{link}\"><code>{path}</code></a>; {n} checks in {s:.2} s</p>\
         <div class=\"prov\"><b>Provenance.</b> {src}{notes}</div>",
        id = esc(&case.id),
        title = esc(&case.title),
        link = esc(&link),
        // The case's path from the suite's root (the report's folder's parent), never this
        // machine's absolute path: a report sent to a colleague names files they have.
        path = esc(&relative_link(&case.path, dir.parent().unwrap_or(dir))),
        n = c.ran.results.len(),
        s = c.ran.seconds,
        src = esc(&case.provenance.source),
        notes = case
            .provenance
            .notes
            .as_deref()
            .map(|n| format!("<br><b>Notes.</b> {}", esc(n)))
            .unwrap_or_default()
    );
    h += &data_as_read_html(case, dir);
    if !c.ran.corrections.is_empty() {
        let _ = write!(
            h,
            "<p class=\"xfail\">Run with corrections: {}</p>",
            esc(&c.ran.corrections.join("; "))
        );
    }
    let figs = figures::of_case(c);
    if !figs.is_empty() {
        h += &figures_html(&case.id, &figs);
    }
    h += "<table><tr><th>check</th><th>quantity</th><th>value</th><th>expected</th>\
          <th>allowed</th><th>tolerance and reason</th><th>margin</th><th>verdict</th></tr>";
    for r in &c.ran.results {
        let rows = r.quantities.len().max(1);
        let class = outcome_class(r.outcome);
        let head = format!(
            "<td rowspan=\"{rows}\" id=\"check-{cid}-{k}\"><a href=\"{link}\">{k}</a><br><span class=\"muted\">{kind}</span></td>",
            cid = esc(&case.id),
            k = esc(&r.check),
            kind = r.kind.name(),
            link = esc(&link)
        );
        let mut verdict = format!("<span class=\"badge {class}\">{}</span>", r.outcome.label());
        if let Some((want, got)) = r.verdict {
            let _ = write!(
                verdict,
                "<br><span class=\"muted\">BCAR: expected {want:?}, computed {got:?}</span>"
            );
        }
        if let Some(why) = &r.expected_failure {
            let _ = write!(
                verdict,
                "<div class=\"why\">expected to fail: {}</div>",
                esc(why)
            );
        }
        verdict += &corrections_labels(r);
        let vcell = format!("<td rowspan=\"{rows}\">{verdict}</td>");
        if r.quantities.is_empty() {
            let (class, text) = match (&r.error, &r.plot) {
                (Some(e), _) => ("fail", esc(e)),
                (
                    None,
                    Some(crate::suite::outcome::PlotData::Modes {
                        selected: Some(e), ..
                    }),
                ) => (
                    "",
                    format!(
                        "the verdict only; the mode: eigenvalue {} ± {}i 1/s",
                        num(e.re),
                        num(e.im.abs())
                    ),
                ),
                (None, _) => ("", "the verdict only".to_string()),
            };
            let _ = write!(
                h,
                "<tr>{head}<td colspan=\"6\" class=\"{class}\">{text}</td>{vcell}</tr>"
            );
            continue;
        }
        for (i, q) in r.quantities.iter().enumerate() {
            let _ = write!(
                h,
                "<tr>{}<td>{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td><td>{}</td>\
                 <td><b>{}</b>: {}</td><td class=\"n {}\">{}</td>{}</tr>",
                if i == 0 { head.as_str() } else { "" },
                esc(&q.quantity),
                num(q.value),
                q.expected.map_or("-".into(), num),
                esc(&q.allowed),
                esc(&q.tolerance),
                esc(&q.reason),
                if q.pass { "pass" } else { "fail" },
                num(q.margin),
                if i == 0 { vcell.as_str() } else { "" },
            );
        }
    }
    h += "</table>";
    if let Some(study) = &c.sensitivity {
        h += &sensitivity::html(study);
    }
    h += "</section>\n";
    h
}

/// The summary as Markdown: counts, versions, corrections, the slowest cases, one row per
/// case, and every check that needs a look (failures and unexpected passes) explained.
pub fn markdown(run: &Run) -> String {
    let k = run.counts();
    let mut m = String::from("# cierva validation summary\n\n");
    let _ = writeln!(
        m,
        "{}, {} in {:.1} s: **{}**, {}.\n\nBy class (only validation compares the model with measured data):\n",
        crate::units::count(run.cases.len(), "case", "cases"),
        crate::units::count(k.total(), "check", "checks"),
        run.seconds,
        k.describe(),
        crate::units::count(run.input_errors.len(), "input error", "input errors")
    );
    for (class, c) in crate::report::tables::counts_by_class(&run.results()) {
        let _ = writeln!(
            m,
            "- {}: {}: {}",
            class.name(),
            crate::units::count(c.total(), "check", "checks"),
            c.describe()
        );
    }
    let verdicts = crate::uncertainty::propagate::VerdictCounts::of(
        run.cases
            .iter()
            .filter_map(|c| c.uncertainty.as_ref())
            .flat_map(|u| &u.results),
    );
    if verdicts.total() + verdicts.apart() > 0 {
        let _ = writeln!(
            m,
            "\nUncertainty (ASME V&V 20), validation quantities: {}.",
            verdicts.describe()
        );
    }
    m += "\n";
    for (name, v) in versions() {
        let _ = writeln!(m, "- {name}: {v}");
    }
    if run.corrections.is_empty() {
        m += "- corrections: none given\n";
    }
    for (p, d) in &run.corrections {
        let _ = writeln!(m, "- corrections `{}`: {d}", p.display());
    }
    m += "\nTime is each case's checks, summed over the threads that ran them; a linearisation that several cases share is computed \
          once, by the first case that needs it.\n\n| case | class | checks | pass | FAIL | xfail | MOVED | XPASS | ERROR | time, s |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for c in &run.cases {
        let n = crate::report::tables::counts(&c.ran.results);
        let _ = writeln!(
            m,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            c.ran.case.id,
            c.ran.case.class.name(),
            c.ran.results.len(),
            n.pass,
            n.fail,
            n.expected_failure,
            n.discrepancy_moved,
            n.unexpected_pass,
            n.error,
            c.ran.seconds
        );
    }
    let bad: Vec<&CheckResult> = run
        .cases
        .iter()
        .flat_map(|c| c.ran.results.iter())
        .filter(|r| !r.outcome.ok())
        .collect();
    if !bad.is_empty() {
        m += "\n## Needs a look\n\n";
        for r in bad {
            let _ = writeln!(m, "```\n{}\n```", r.explain());
        }
    }
    for e in &run.input_errors {
        let _ = writeln!(m, "\n```\n{e}\n```");
    }
    m
}

/// Writes `index.html` and `summary.md` into `dir` (made if missing); the paths written.
pub fn write(run: &Run, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let index = dir.join("index.html");
    let summary = dir.join("summary.md");
    std::fs::write(&index, html(run, dir))?;
    std::fs::write(&summary, markdown(run))?;
    Ok(vec![index, summary])
}

/// What a check's verdict cell says of the corrections applied to it: an extrapolation beyond
/// the domain they were fitted on, and whether it was one of their fit's targets.
fn corrections_labels(r: &crate::suite::outcome::CheckResult) -> String {
    let mut h = String::new();
    if let Some(x) = &r.extrapolation {
        let _ = write!(h, "<div class=\"why\">{}</div>", esc(x));
    }
    if let Some(by) = &r.calibrated_on {
        let _ = write!(
            h,
            "<div class=\"why\">calibrated on: a target of the fit of {}, so no evidence for it</div>",
            esc(by)
        );
    }
    h
}

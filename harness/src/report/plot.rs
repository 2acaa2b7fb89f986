//! Figures for the report, drawn as SVG by plotters (no fonts or system libraries: the text is
//! `<text font-family="sans-serif">`, drawn by the browser).
//!
//! A [`Figure`] is data only: lines, markers, vertical bars (a reference's allowed range),
//! bands (a tolerance around a reference trace) and interval whiskers (a model's spread at
//! scattered points). The axes span the finite data; a bar or band
//! end far outside it (a sign check's `[0, 1e6]`) is clipped to the frame, so it reads as
//! "everything above zero". A figure without a finite point is not drawn at all.

use plotters::prelude::*;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Line,
    Markers,
    LineMarkers,
    /// Hollow rings, larger than markers: to pick out points drawn by another series.
    Rings,
    /// Hollow markers, the size of markers: points of the same data set apart (a reference's
    /// frequencies below its coherence threshold, which its comparison leaves out).
    Hollow,
}

/// One named series of points.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// A colour of the palette (0 blue, 1 red, 2 green, 7 grey), instead of the series' place.
    pub colour: Option<usize>,
}

/// A reference's allowed range at one abscissa (a flight 95 % bound, a tolerance).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bar {
    pub x: f64,
    pub lower: f64,
    pub upper: f64,
    /// The expected value, if there is one (drawn as a tick).
    pub expected: Option<f64>,
}

/// A shaded band, `(x, lower, upper)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Shade {
    pub name: String,
    pub points: Vec<(f64, f64, f64)>,
}

/// A figure: axes, series, bars and bands.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// The bars and the legend entry they share.
    pub bars: Vec<Bar>,
    pub bars_name: String,
    pub bands: Vec<Shade>,
    /// Intervals of the model at scattered points (its 95 % over the inputs where the points
    /// do not make a line, as a table's rows at several rotor speeds per mu): thin coloured
    /// whiskers beside the reference bars, under one legend entry.
    pub intervals: Option<Shade>,
    /// Draw the vertical axis `x = 0` (the complex plane's imaginary axis).
    pub x_zero: bool,
    /// The abscissae are decimal logarithms: the axis is labelled with their powers of ten (a
    /// Bode figure's frequency).
    pub log_x: bool,
    /// Drawn stacked with the figures next to it that share this caption, on one abscissa (a
    /// Bode diagram's magnitude, phase and coherence), under the caption.
    pub stack: Option<String>,
}

/// The vertical pixels of a panel that are not plotting area: the caption, the x labels and
/// the margins (`draw_on`'s chart).
const PLOT_FRAME_PX: f64 = 8.0 * 2.0 + 36.0 + 24.0;

/// A legend's height, px: its frame and padding, and each entry's row (11 px labels).
const LEGEND_PAD_PX: f64 = 14.0;
const LEGEND_ROW_PX: f64 = 16.0;

/// The most of a panel's plotting height the legend's strip may take: a legend taller than
/// this (a dozen entries on a short panel) may cover the top of the data.
const LEGEND_STRIP_MAX: f64 = 0.6;

/// Values beyond this magnitude are "no bound" (a sign check's interval) and are left out of
/// the axis ranges.
const NO_BOUND: f64 = 1e5;

fn colour(i: usize) -> RGBColor {
    const C: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
        RGBColor(255, 127, 14),
        RGBColor(23, 190, 207),
        RGBColor(140, 86, 75),
        RGBColor(127, 127, 127),
    ];
    C[i % C.len()]
}

fn finite(v: f64) -> bool {
    v.is_finite() && v.abs() < NO_BOUND
}

impl Figure {
    /// The finite data points drawn (series points, bar ends, band points).
    pub fn points(&self) -> usize {
        let s: usize = self
            .series
            .iter()
            .map(|s| {
                s.points
                    .iter()
                    .filter(|(x, y)| finite(*x) && finite(*y))
                    .count()
            })
            .sum();
        let b = self
            .bars
            .iter()
            .filter(|b| finite(b.x) && (finite(b.lower) || finite(b.upper)))
            .count();
        let d: usize = self
            .bands
            .iter()
            .chain(&self.intervals)
            .map(|b| b.points.iter().filter(|p| finite(p.0)).count())
            .sum();
        s + b + d
    }

    fn ranges(&self) -> Option<((f64, f64), (f64, f64))> {
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for s in &self.series {
            for &(x, y) in &s.points {
                if finite(x) && finite(y) {
                    xs.push(x);
                    ys.push(y);
                }
            }
        }
        for b in &self.bars {
            if finite(b.x) {
                xs.push(b.x);
                ys.extend([b.lower, b.upper].into_iter().filter(|v| finite(*v)));
            }
        }
        for b in self.bands.iter().chain(&self.intervals) {
            for &(x, lo, hi) in &b.points {
                if finite(x) {
                    xs.push(x);
                    ys.extend([lo, hi].into_iter().filter(|v| finite(*v)));
                }
            }
        }
        if self.x_zero {
            xs.push(0.0);
        }
        // The series set the scale: a reference end far beyond them (a sign check's bound of
        // 1000) would flatten them to a line, so ends further than twice the series' spread or
        // twice their largest magnitude are left to run off the frame.
        let own: Vec<f64> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|(x, y)| finite(*x) && finite(*y))
            .map(|p| p.1)
            .collect();
        if !own.is_empty() {
            let lo = own.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = own.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let reach = (2.0 * (hi - lo))
                .max(2.0 * lo.abs().max(hi.abs()))
                .max(1e-9);
            ys.retain(|y| *y >= lo - reach && *y <= hi + reach);
        }
        let span = |v: &[f64]| -> Option<(f64, f64)> {
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if !(lo.is_finite() && hi.is_finite()) {
                return None;
            }
            let pad = if hi > lo {
                0.06 * (hi - lo)
            } else {
                0.1 * lo.abs().max(1.0)
            };
            Some((lo - pad, hi + pad))
        };
        Some((span(&xs)?, span(&ys)?))
    }

    /// How many entries the legend has: one per series, band and interval set, and one for
    /// the bars.
    fn legend_entries(&self) -> usize {
        self.series.len()
            + self.bands.len()
            + usize::from(self.intervals.is_some())
            + usize::from(!self.bars.is_empty())
    }

    /// The figure as an SVG document, or `None` when it has nothing finite to show.
    pub fn svg(&self, width: u32, height: u32) -> Option<String> {
        panels_svg(std::slice::from_ref(self), width, height)
    }

    /// Draws the figure on an area (of an SVG document); with `log_x`, its abscissae are
    /// decimal logarithms and the axis is labelled with their powers of ten.
    fn draw_on(
        &self,
        root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
        log_x: bool,
    ) -> Result<(), Box<dyn std::error::Error>> {
        let Some(((x0, x1), (y0, y_data))) = self.ranges() else {
            return Ok(());
        };
        // A strip at the top for the legend, as tall as its entries, where nothing is drawn:
        // every mark is clipped to the data's top, so the legend covers none.
        let plot_px = f64::from(root.dim_in_pixel().1).max(1.0) - PLOT_FRAME_PX;
        let legend_px = LEGEND_PAD_PX + LEGEND_ROW_PX * self.legend_entries() as f64;
        let strip = (legend_px / plot_px.max(legend_px)).min(LEGEND_STRIP_MAX);
        let y1 = y_data + (y_data - y0) * strip / (1.0 - strip);
        {
            let mut chart = ChartBuilder::on(root)
                .caption(&self.title, ("sans-serif", 15))
                .margin(8)
                .x_label_area_size(36)
                .y_label_area_size(62)
                .build_cartesian_2d(x0..x1, y0..y1)?;
            let powers = |v: &f64| crate::units::sig(10f64.powf(*v), 2);
            let plain = |v: &f64| tick_label(*v, x1 - x0);
            let x_labels: &dyn Fn(&f64) -> String = if log_x { &powers } else { &plain };
            let y_labels = |v: &f64| tick_label(*v, y1 - y0);
            chart
                .configure_mesh()
                .x_label_formatter(x_labels)
                .y_label_formatter(&y_labels)
                .x_desc(self.x_label.as_str())
                .y_desc(self.y_label.as_str())
                .label_style(("sans-serif", 11))
                .max_light_lines(0)
                .bold_line_style(RGBColor(232, 232, 232))
                .draw()?;
            if self.x_zero {
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(0.0, y0), (0.0, y1)],
                    BLACK.mix(0.5).stroke_width(1),
                )))?;
            }
            self.draw_bands(&mut chart, (y0, y_data))?;
            if let Some(b) = &self.intervals {
                draw_intervals(&mut chart, b, x1 - x0, (y0, y_data))?;
            }
            if !self.bars.is_empty() {
                self.draw_bars(&mut chart, x1 - x0, (y0, y_data))?;
            }
            self.draw_series(&mut chart, (y0, y_data))?;
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.4))
                .label_font(("sans-serif", 11))
                .draw()?;
        }
        Ok(())
    }

    /// The bands, each a filled polygon between its lower and upper bounds (clipped to the
    /// data's range `(y0, y_data)`), with its legend entry.
    fn draw_bands(&self, chart: &mut Chart<'_, '_>, (y0, y_data): (f64, f64)) -> DrawResult {
        let clip = |v: f64| v.clamp(y0, y_data);
        for (i, b) in self.bands.iter().enumerate() {
            let c = colour(i + 7);
            let pts: Vec<(f64, f64, f64)> = b
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite() && p.2.is_finite())
                .collect();
            let mut poly: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, clip(p.2))).collect();
            poly.extend(pts.iter().rev().map(|p| (p.0, clip(p.1))));
            chart
                .draw_series(std::iter::once(Polygon::new(poly, c.mix(0.25).filled())))?
                .label(b.name.as_str())
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 16, y + 5)], c.mix(0.25).filled())
                });
        }
        Ok(())
    }

    /// The bars: a line from each bar's lower to its upper bound (clipped to the data's range
    /// `(y0, y_data)`) with its legend entry, caps a share of the axis' `width` wide where the
    /// bounds are in range, and a cross at each expected value in range.
    fn draw_bars(
        &self,
        chart: &mut Chart<'_, '_>,
        width: f64,
        (y0, y_data): (f64, f64),
    ) -> DrawResult {
        let clip = |v: f64| v.clamp(y0, y_data);
        let style = BLACK.stroke_width(2);
        let bars: Vec<Bar> = self
            .bars
            .iter()
            .copied()
            .filter(|b| b.x.is_finite() && !b.lower.is_nan() && !b.upper.is_nan())
            .collect();
        let dx = 0.012 * width;
        chart
            .draw_series(bars.iter().map(move |b| {
                PathElement::new(vec![(b.x, clip(b.lower)), (b.x, clip(b.upper))], style)
            }))?
            .label(self.bars_name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x + 8, y - 6), (x + 8, y + 6)], style));
        let caps: Vec<(f64, f64)> = bars
            .iter()
            .flat_map(|b| [(b.x, b.lower), (b.x, b.upper)])
            .filter(|(_, v)| *v >= y0 && *v <= y_data)
            .collect();
        chart.draw_series(
            caps.iter()
                .map(|&(x, v)| PathElement::new(vec![(x - dx, v), (x + dx, v)], style)),
        )?;
        chart.draw_series(bars.iter().filter_map(move |b| {
            let e = b.expected.filter(|v| *v >= y0 && *v <= y_data)?;
            Some(Cross::new((b.x, e), 4, BLACK.stroke_width(1)))
        }))?;
        Ok(())
    }

    /// The series, each as lines, markers or rings (clipped to the data's range
    /// `(y0, y_data)`), with its legend entry.
    fn draw_series(&self, chart: &mut Chart<'_, '_>, (y0, y_data): (f64, f64)) -> DrawResult {
        let clip = |v: f64| v.clamp(y0, y_data);
        for (i, s) in self.series.iter().enumerate() {
            let c = colour(s.colour.unwrap_or(i));
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .map(|(x, y)| (x, clip(y)))
                .collect();
            let line = matches!(s.style, Style::Line | Style::LineMarkers);
            let markers = matches!(s.style, Style::Markers | Style::LineMarkers);
            if line {
                chart
                    .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))?
                    .label(s.name.as_str())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2))
                    });
            }
            if markers {
                let a = chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, c.filled())))?;
                if !line {
                    a.label(s.name.as_str())
                        .legend(move |(x, y)| Circle::new((x + 8, y), 3, c.filled()));
                }
            }
            if s.style == Style::Hollow {
                let edge = c.stroke_width(1);
                chart
                    .draw_series(pts.iter().map(|p| Circle::new(*p, 3, edge)))?
                    .label(s.name.as_str())
                    .legend(move |(x, y)| Circle::new((x + 8, y), 3, edge));
            }
            if s.style == Style::Rings {
                let ring = c.stroke_width(2);
                chart
                    .draw_series(pts.iter().map(|p| Circle::new(*p, 7, ring)))?
                    .label(s.name.as_str())
                    .legend(move |(x, y)| Circle::new((x + 8, y), 6, ring));
            }
        }
        Ok(())
    }
}

/// An interval set: a line from each interval's lower to its upper bound (clipped to the
/// data's range `(y0, y_data)`), offset to the right of the reference bar at the same x by a
/// share of the axis' `width`, with its legend entry.
fn draw_intervals(
    chart: &mut Chart<'_, '_>,
    b: &Shade,
    width: f64,
    (y0, y_data): (f64, f64),
) -> DrawResult {
    let clip = |v: f64| v.clamp(y0, y_data);
    // Offset to the right of the reference bar at the same x.
    let c = colour(7);
    let dx = 0.006 * width;
    let style = c.stroke_width(1);
    chart
        .draw_series(
            b.points
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite() && p.2.is_finite())
                .map(move |p| {
                    PathElement::new(vec![(p.0 + dx, clip(p.1)), (p.0 + dx, clip(p.2))], style)
                }),
        )?
        .label(b.name.as_str())
        .legend(move |(x, y)| PathElement::new(vec![(x + 8, y - 6), (x + 8, y + 6)], style));
    Ok(())
}

/// The chart a figure is drawn on: an SVG area with linear axes.
type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// What drawing returns.
type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// Figures stacked in one SVG document, one panel each (`width` by `panel_height`), or `None`
/// when none has anything finite to show.
pub fn panels_svg(figures: &[Figure], width: u32, panel_height: u32) -> Option<String> {
    panels(figures, width, panel_height, false)
}

/// [`panels_svg`] on a logarithmic abscissa: each figure's `x` values are decimal logarithms
/// (as [`bode_panels`] writes them), labelled with their powers of ten.
pub fn log_x_panels_svg(figures: &[Figure], width: u32, panel_height: u32) -> Option<String> {
    panels(figures, width, panel_height, true)
}

/// A Bode figure's panels on a logarithmic frequency axis: the magnitude (dB) and phase (deg)
/// of each response, and the coherence of the first (the records'), over `frequencies_hz`. A
/// response is `None` where it is not estimated. The phases are unwrapped along each response
/// (a jump of more than 180 deg between neighbours is taken as a wrap), and each is then moved
/// by whole turns to start within 180 deg of the first response's, so the curves compare.
pub fn bode_panels(
    title: &str,
    frequencies_hz: &[f64],
    responses: &[(&str, Vec<Option<rustfft::num_complex::Complex64>>)],
    coherence: &[f64],
    coherence_min: f64,
) -> Vec<Figure> {
    let x: Vec<f64> = frequencies_hz.iter().map(|f| f.log10()).collect();
    let styles = |i: usize| if i == 0 { Style::Markers } else { Style::Line };
    let unwrap = |h: &[Option<rustfft::num_complex::Complex64>]| {
        let mut out = Vec::new();
        let mut last: Option<f64> = None;
        for (xk, v) in x.iter().zip(h) {
            if let Some(v) = v {
                let mut deg = v.arg().to_degrees();
                if let Some(l) = last {
                    deg -= 360.0 * ((deg - l) / 360.0).round();
                }
                last = Some(deg);
                out.push((*xk, deg));
            }
        }
        out
    };
    let mut phases: Vec<Vec<(f64, f64)>> = responses.iter().map(|(_, h)| unwrap(h)).collect();
    let anchor = phases.first().and_then(|p| p.first().map(|q| q.1));
    if let Some(a) = anchor {
        for p in phases.iter_mut().skip(1) {
            let shift = p
                .first()
                .map_or(0.0, |q| 360.0 * ((q.1 - a) / 360.0).round());
            p.iter_mut().for_each(|q| q.1 -= shift);
        }
    }
    // Whether the first response (the records') is coherent enough at abscissa `xk` to count.
    let coherent = |xk: f64| {
        x.iter()
            .position(|v| *v == xk)
            .and_then(|k| coherence.get(k))
            .is_some_and(|g| *g >= coherence_min)
    };
    let below = format!("coherence below {coherence_min}: not compared");
    let series = |values: Vec<Vec<(f64, f64)>>| -> Vec<Series> {
        let mut out = Vec::new();
        for (i, ((name, _), points)) in responses.iter().zip(values).enumerate() {
            if i > 0 {
                out.push(Series {
                    name: name.to_string(),
                    points,
                    style: styles(i),
                    colour: Some(i),
                });
                continue;
            }
            let (kept, apart): (Vec<_>, Vec<_>) = points.into_iter().partition(|p| coherent(p.0));
            out.push(Series {
                name: name.to_string(),
                points: kept,
                style: styles(0),
                colour: Some(0),
            });
            if !apart.is_empty() {
                out.push(Series {
                    name: format!("{name}, {below}"),
                    points: apart,
                    style: Style::Hollow,
                    colour: Some(7),
                });
            }
        }
        out
    };
    let magnitudes = responses
        .iter()
        .map(|(_, h)| {
            x.iter()
                .zip(h)
                .filter_map(|(xk, v)| v.map(|v| (*xk, 20.0 * v.norm().log10())))
                .collect()
        })
        .collect();
    let x_label = "frequency, Hz (log scale)".to_string();
    let stack = Some(format!("{title}: magnitude, phase and coherence"));
    vec![
        Figure {
            title: format!("{title}: magnitude"),
            x_label: x_label.clone(),
            y_label: "magnitude, dB".into(),
            series: series(magnitudes),
            log_x: true,
            stack: stack.clone(),
            ..Figure::default()
        },
        Figure {
            title: format!("{title}: phase"),
            x_label: x_label.clone(),
            y_label: "phase, deg".into(),
            series: series(phases),
            log_x: true,
            stack: stack.clone(),
            ..Figure::default()
        },
        coherence_panel(title, &x, coherence, coherence_min, stack),
    ]
}

/// A Bode figure's coherence panel (abscissae `x`, decimal logarithms of the frequencies): the
/// coherent frequencies as markers, those below `coherence_min` hollow and grey, and the
/// threshold as a line.
fn coherence_panel(
    title: &str,
    x: &[f64],
    coherence: &[f64],
    coherence_min: f64,
    stack: Option<String>,
) -> Figure {
    let (kept, apart): (Vec<_>, Vec<_>) = x
        .iter()
        .copied()
        .zip(coherence.iter().copied())
        .partition(|(_, g)| *g >= coherence_min);
    let span = x
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let mut coherence_series = vec![
        Series {
            name: "coherence".into(),
            points: kept,
            style: Style::Markers,
            colour: Some(2),
        },
        Series {
            name: format!("threshold {coherence_min}"),
            points: vec![(span.0, coherence_min), (span.1, coherence_min)],
            style: Style::Line,
            colour: Some(7),
        },
    ];
    if !apart.is_empty() {
        coherence_series.insert(
            1,
            Series {
                name: format!("coherence below {coherence_min}: not compared"),
                points: apart,
                style: Style::Hollow,
                colour: Some(7),
            },
        );
    }
    Figure {
        title: format!("{title}: coherence of the records' estimate"),
        x_label: "frequency, Hz (log scale)".into(),
        y_label: "coherence".into(),
        series: coherence_series,
        log_x: true,
        stack,
        ..Figure::default()
    }
}

fn panels(figures: &[Figure], width: u32, panel_height: u32, log_x: bool) -> Option<String> {
    if figures.iter().all(|f| f.points() == 0) {
        return None;
    }
    let mut out = String::new();
    let drawn = (|| -> Result<(), Box<dyn std::error::Error>> {
        let height = panel_height * figures.len() as u32;
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        let areas = root.split_evenly((figures.len(), 1));
        for (f, area) in figures.iter().zip(&areas) {
            f.draw_on(area, log_x || f.log_x)?;
        }
        root.present()?;
        Ok(())
    })();
    drawn.ok()?;
    Some(out)
}

/// One point of a sparkline: its label (shown on hover) and value.
pub struct Spark {
    pub label: String,
    pub value: f64,
}

/// Width and height of a sparkline, px: a table cell's worth.
const SPARK_SIZE_PX: (f64, f64) = (132.0, 30.0);

/// A score's history as a small inline SVG: the committed values oldest first, then `now`, as
/// a line with a dot per value (each with its label on hover), the last dot ringed. Values that
/// are not finite are left out; `None` when nothing finite is left. The vertical scale is the
/// values' own range (a flat line through the middle when they are equal): it shows the
/// direction and the steps, the numbers are beside it.
pub fn sparkline_svg(history: &[Spark], now: &Spark) -> Option<String> {
    use std::fmt::Write;
    let points: Vec<&Spark> = history
        .iter()
        .chain(std::iter::once(now))
        .filter(|p| p.value.is_finite())
        .collect();
    if points.is_empty() {
        return None;
    }
    let (w, h) = SPARK_SIZE_PX;
    let pad = 4.0;
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), p| {
            (l.min(p.value), u.max(p.value))
        });
    let n = points.len();
    let x = |i: usize| {
        if n == 1 {
            w / 2.0
        } else {
            pad + (w - 2.0 * pad) * i as f64 / (n - 1) as f64
        }
    };
    let y = |v: f64| {
        if hi > lo {
            h - pad - (h - 2.0 * pad) * (v - lo) / (hi - lo)
        } else {
            h / 2.0
        }
    };
    let escape = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
            .replace('"', "&quot;")
    };
    let mut svg = format!(
        "<svg class=\"spark\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" role=\"img\"><polyline fill=\"none\" stroke=\"#4a6fa5\" stroke-width=\"1.5\" points=\""
    );
    for (i, p) in points.iter().enumerate() {
        let _ = write!(svg, "{:.1},{:.1} ", x(i), y(p.value));
    }
    svg.push_str("\"/>");
    for (i, p) in points.iter().enumerate() {
        let last = i + 1 == n;
        let _ = write!(
            svg,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"{}\" fill=\"{}\" stroke=\"#1f3b63\" stroke-width=\"{}\"><title>{}: {}</title></circle>",
            x(i),
            y(p.value),
            if last { 3.0 } else { 2.0 },
            if last { "#ffffff" } else { "#4a6fa5" },
            if last { 1.5 } else { 0.0 },
            escape(&p.label),
            p.value
        );
    }
    svg.push_str("</svg>");
    Some(svg)
}

/// An axis tick's label: to the decimals the axis's `span` needs (three significant digits of
/// the span), trailing zeros dropped, and a tick that is zero but for rounding (a step of the
/// axis summed from a negative start, `-2.2e-16`) written `0`.
pub fn tick_label(v: f64, span: f64) -> String {
    let span = span.abs();
    if !(v.is_finite() && span.is_finite() && span > 0.0) {
        return format!("{v}");
    }
    if v.abs() <= 1e-9 * span {
        return "0".into();
    }
    let decimals = (2.0 - span.log10().floor()).clamp(0.0, 12.0) as usize;
    let text = format!("{v:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    };
    if text == "-0" { "0".into() } else { text }
}

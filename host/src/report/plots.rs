//! SVG figures (plotters, SVG backend: no fonts or system libraries needed).

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

pub use crate::figure::{MapCell, Series, Style};

/// An error while drawing, with the file it concerns.
pub type PlotResult = Result<(), String>;

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.05 * lo.abs().max(1e-12)
    };
    (lo - pad, hi + pad)
}

fn colour(index: usize) -> RGBColor {
    let (r, g, b) = Palette99::pick(index).to_rgba().rgb();
    RGBColor(r, g, b)
}

/// The axes of a 720 x 450 chart: caption, label areas, mesh and axis labels.
fn frame<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    error: &dyn Fn(&dyn std::fmt::Display) -> String,
) -> Result<ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>, String> {
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| error(&e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .draw()
        .map_err(|e| error(&e))?;
    Ok(chart)
}

/// The corner of the axes whose legend box covers the fewest data points (matplotlib's
/// `loc = "best"`): the box is about 40 % of the width and a line per series high; lines are
/// sampled between their points too. Ties keep the order upper right, upper left, lower right,
/// lower left.
fn emptiest_corner(
    series: &[&[(f64, f64)]],
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> SeriesLabelPosition {
    let (width, height) = (x1 - x0, y1 - y0);
    let box_width = 0.4 * width;
    let box_height = (0.06 * series.len() as f64 + 0.04).min(0.9) * height;
    let mut samples = Vec::new();
    for points in series {
        for pair in points.windows(2) {
            for k in 0..4 {
                let t = f64::from(k) / 4.0;
                samples.push((
                    pair[0].0 + t * (pair[1].0 - pair[0].0),
                    pair[0].1 + t * (pair[1].1 - pair[0].1),
                ));
            }
        }
        samples.extend(points.last().copied());
    }
    let corners = [
        (
            SeriesLabelPosition::UpperRight,
            x1 - box_width,
            y1 - box_height,
        ),
        (SeriesLabelPosition::UpperLeft, x0, y1 - box_height),
        (SeriesLabelPosition::LowerRight, x1 - box_width, y0),
        (SeriesLabelPosition::LowerLeft, x0, y0),
    ];
    let covered = |left: f64, bottom: f64| {
        samples
            .iter()
            .filter(|(x, y)| {
                (left..=left + box_width).contains(x) && (bottom..=bottom + box_height).contains(y)
            })
            .count()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (position, left, bottom) in corners {
        let count = covered(left, bottom);
        if count < best.0 {
            best = (count, position);
        }
    }
    best.1
}

/// Draw the legend of a [`frame`] chart at `position` and write the file.
fn finish<'a, 'b: 'a>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    root: &DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    position: SeriesLabelPosition,
    error: &dyn Fn(&dyn std::fmt::Display) -> String,
) -> PlotResult {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| error(&e))?;
    root.present().map_err(|e| error(&e))
}

/// A line/marker chart of several series.
pub fn line_chart(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> PlotResult {
    let error = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let root = SVGBackend::new(path, (720, 450)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let (x0, x1) = range(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    // The error bars are inside the axes too.
    let (y0, y1) = range(series.iter().flat_map(|s| {
        s.points.iter().enumerate().flat_map(|(i, p)| {
            let e = s
                .errors
                .get(i)
                .copied()
                .filter(|e| e.is_finite())
                .unwrap_or(0.0);
            [p.1 - e, p.1 + e]
        })
    }));
    let mut chart = frame(&root, title, x_label, y_label, (x0, x1), (y0, y1), &error)?;
    for s in series {
        let c = colour(s.colour);
        let points = s
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite());
        match s.style {
            Style::Line => chart
                .draw_series(LineSeries::new(points, c.stroke_width(2)))
                .map_err(|e| error(&e))?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2))
                }),
            Style::Dashed => chart
                .draw_series(DashedLineSeries::new(points, 8, 5, c.stroke_width(2)))
                .map_err(|e| error(&e))?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 6, y)], c.stroke_width(2))
                }),
            Style::Markers => {
                draw_markers(&mut chart, s, false, &error)?;
                continue;
            }
        };
    }
    let all: Vec<&[(f64, f64)]> = series.iter().map(|s| s.points.as_slice()).collect();
    let position = emptiest_corner(&all, (x0, x1), (y0, y1));
    finish(&mut chart, &root, position, &error)
}

/// A marker series with its legend entry, and its error bars (vertical, or horizontal if
/// `errors_along_x`).
fn draw_markers<'a, 'b: 'a>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    series: &Series,
    errors_along_x: bool,
    error: &dyn Fn(&dyn std::fmt::Display) -> String,
) -> PlotResult {
    let c = colour(series.colour);
    draw_error_bars(chart, series, c, errors_along_x, error)?;
    chart
        .draw_series(
            series
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .map(|p| Circle::new(p, 4, c.filled())),
        )
        .map_err(|e| error(&e))?
        .label(series.label.clone())
        .legend(move |(x, y)| Circle::new((x + 8, y), 4, c.filled()));
    Ok(())
}

/// The error bars of a marker series: `errors[i]` either side of point `i`, vertical (or
/// horizontal if `along_x`).
fn draw_error_bars<'a, 'b: 'a>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    series: &Series,
    c: RGBColor,
    along_x: bool,
    error: &dyn Fn(&dyn std::fmt::Display) -> String,
) -> PlotResult {
    let bars = series
        .points
        .iter()
        .zip(&series.errors)
        .filter(|((x, y), e)| x.is_finite() && y.is_finite() && e.is_finite() && **e > 0.0)
        .map(|(&(x, y), &e)| {
            let ends = if along_x {
                vec![(x - e, y), (x + e, y)]
            } else {
                vec![(x, y - e), (x, y + e)]
            };
            PathElement::new(ends, c.stroke_width(1))
        });
    chart.draw_series(bars).map_err(|e| error(&e))?;
    Ok(())
}

/// A parity chart: each series' points are `(recorded, predicted)` with the recorded
/// uncertainty as horizontal error bars, over the line `predicted = recorded`.
pub fn parity_chart(path: &Path, title: &str, label: &str, series: &[Series]) -> PlotResult {
    let error = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let root = SVGBackend::new(path, (720, 450)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let (lo, hi) = range(
        series
            .iter()
            .flat_map(|s| s.points.iter().flat_map(|p| [p.0, p.1])),
    );
    let mut chart = frame(
        &root,
        title,
        &format!("recorded {label}"),
        &format!("simulated {label}"),
        (lo, hi),
        (lo, hi),
        &error,
    )?;
    chart
        .draw_series(DashedLineSeries::new(
            [(lo, lo), (hi, hi)],
            6,
            4,
            BLACK.mix(0.6).stroke_width(1),
        ))
        .map_err(|e| error(&e))?
        .label("simulated = recorded")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.stroke_width(1)));
    for s in series {
        draw_markers(&mut chart, s, true, &error)?;
    }
    let mut all: Vec<&[(f64, f64)]> = series.iter().map(|s| s.points.as_slice()).collect();
    let diagonal = [(lo, lo), (hi, hi)];
    all.push(&diagonal);
    let position = emptiest_corner(&all, (lo, hi), (lo, hi));
    finish(&mut chart, &root, position, &error)
}

/// A stacked histogram of several groups of values over one set of `bins` bins, one colour
/// per group with its label (seed 000 fig. 14: the tracked states per experiment type).
pub fn histogram(
    path: &Path,
    title: &str,
    x_label: &str,
    groups: &[(String, Vec<f64>)],
    bins: usize,
) -> PlotResult {
    let error = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let bins = bins.max(1);
    let finite =
        |values: &[f64]| -> Vec<f64> { values.iter().copied().filter(|v| v.is_finite()).collect() };
    let (lo, hi) = range(groups.iter().flat_map(|(_, v)| finite(v)));
    let width = (hi - lo) / bins as f64;
    let counts: Vec<Vec<usize>> = groups
        .iter()
        .map(|(_, values)| {
            let mut counts = vec![0usize; bins];
            for v in finite(values) {
                let k = (((v - lo) / width) as usize).min(bins - 1);
                counts[k] += 1;
            }
            counts
        })
        .collect();
    let totals: Vec<usize> = (0..bins)
        .map(|k| counts.iter().map(|c| c[k]).sum())
        .collect();
    let top = totals.iter().copied().max().unwrap_or(1).max(1) as f64 * 1.15;
    let root = SVGBackend::new(path, (560, 360)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(lo..hi, 0.0..top)
        .map_err(|e| error(&e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc("count")
        .draw()
        .map_err(|e| error(&e))?;
    let mut below = vec![0usize; bins];
    for (g, ((label, _), counts)) in groups.iter().zip(&counts).enumerate() {
        let fill = colour(g).mix(0.75).filled();
        let bars: Vec<Rectangle<(f64, f64)>> = counts
            .iter()
            .enumerate()
            .filter(|(_, &c)| c > 0)
            .map(|(k, &c)| {
                let x = lo + k as f64 * width;
                let base = below[k] as f64;
                Rectangle::new([(x, base), (x + width, base + c as f64)], fill)
            })
            .collect();
        for (b, c) in below.iter_mut().zip(counts) {
            *b += c;
        }
        chart
            .draw_series(bars)
            .map_err(|e| error(&e))?
            .label(label.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], fill));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| error(&e))?;
    root.present().map_err(|e| error(&e))
}

/// Parallel coordinates of solutions normalised to `[0, 1]` per axis; highlighted lines drawn
/// thick and last.
pub fn parallel_coordinates(
    path: &Path,
    title: &str,
    axes: &[String],
    lines: &[(Vec<f64>, bool)],
) -> PlotResult {
    let error = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let root = SVGBackend::new(path, (760, 420)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let count = axes.len().max(2);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 16))
        .margin(14)
        .x_label_area_size(60)
        .y_label_area_size(50)
        .build_cartesian_2d(-0.2..(count as f64 - 0.8), -0.05..1.05)
        .map_err(|e| error(&e))?;
    let names: Vec<String> = axes.to_vec();
    chart
        .configure_mesh()
        .x_labels(count)
        .x_label_formatter(&|x| names.get(x.round() as usize).cloned().unwrap_or_default())
        .y_desc("position within bounds")
        .disable_x_mesh()
        .draw()
        .map_err(|e| error(&e))?;
    for highlighted in [false, true] {
        for (values, flag) in lines.iter().filter(|l| l.1 == highlighted) {
            let style = if *flag {
                RED.stroke_width(3)
            } else {
                BLUE.mix(0.35).stroke_width(1)
            };
            chart
                .draw_series(LineSeries::new(
                    values.iter().enumerate().map(|(k, v)| (k as f64, *v)),
                    style,
                ))
                .map_err(|e| error(&e))?;
        }
    }
    root.present().map_err(|e| error(&e))
}

/// A shaded interval of the x axis (a significant band of the diagnosis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shade {
    /// Start of the interval.
    pub start: f64,
    /// End of the interval.
    pub end: f64,
}

/// Whitened residuals against position: series of markers, the `+-2` noise band as dashed
/// lines, and shaded significant intervals.
pub fn residual_chart(
    path: &Path,
    title: &str,
    x_label: &str,
    series: &[Series],
    shades: &[Shade],
) -> PlotResult {
    let error = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let root = SVGBackend::new(path, (720, 450)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let xs = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0))
        .chain(shades.iter().flat_map(|s| [s.start, s.end]));
    let (x0, x1) = range(xs);
    let (y0, y1) = range(
        series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1))
            .chain([-3.0, 3.0]),
    );
    let mut chart = frame(
        &root,
        title,
        x_label,
        "(predicted - recorded) / uncertainty",
        (x0, x1),
        (y0, y1),
        &error,
    )?;
    let pad = 0.01 * (x1 - x0);
    chart
        .draw_series(shades.iter().map(|s| {
            Rectangle::new(
                [(s.start - pad, y0), (s.end + pad, y1)],
                RGBColor(255, 200, 120).mix(0.45).filled(),
            )
        }))
        .map_err(|e| error(&e))?
        .label("significant band")
        .legend(|(x, y)| {
            Rectangle::new(
                [(x, y - 5), (x + 16, y + 5)],
                RGBColor(255, 200, 120).filled(),
            )
        });
    for level in [-2.0, 0.0, 2.0] {
        let style = if level == 0.0 {
            BLACK.stroke_width(1)
        } else {
            BLACK.mix(0.5).stroke_width(1)
        };
        chart
            .draw_series(DashedLineSeries::new(
                [(x0, level), (x1, level)],
                6,
                4,
                style,
            ))
            .map_err(|e| error(&e))?;
    }
    for s in series {
        draw_markers(&mut chart, s, false, &error)?;
    }
    // The residuals scatter about zero: the bands and the series all count.
    let mut all: Vec<&[(f64, f64)]> = series.iter().map(|s| s.points.as_slice()).collect();
    let zero = [(x0, 0.0), (x1, 0.0)];
    all.push(&zero);
    let position = emptiest_corner(&all, (x0, x1), (y0, y1));
    finish(&mut chart, &root, position, &error)
}

/// A map of a scalar field over rectangular cells (a section of a 3D mesh), `width` pixels
/// wide and as high as the cells' aspect ratio wants (at least 160): each cell filled by its
/// value on a white-yellow-red-black scale from `low` to `high` (white below `low`).
pub fn field_map(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    cells: &[MapCell],
    (low, high): (f64, f64),
) -> PlotResult {
    let error = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let (x0, x1) = cells
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (r, _)| {
            (a.min(r[0]), b.max(r[1]))
        });
    let (y0, y1) = cells
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (r, _)| {
            (a.min(r[2]), b.max(r[3]))
        });
    if !(x1 > x0 && y1 > y0) {
        return Err(error(&"no cells to draw"));
    }
    let width = 1100u32;
    let plot_width = f64::from(width - 100);
    let height = (plot_width * (y1 - y0) / (x1 - x0)) as u32 + 110;
    let root = SVGBackend::new(path, (width, height.max(160))).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let mut chart = frame(&root, title, x_label, y_label, (x0, x1), (y0, y1), &error)?;
    let shade = |value: f64| -> RGBColor {
        if value.is_nan() || value < low {
            return WHITE;
        }
        let t = ((value - low) / (high - low)).clamp(0.0, 1.0);
        let mix = |a: f64, b: f64, f: f64| (a + (b - a) * f).round() as u8;
        if t < 0.5 {
            let f = 2.0 * t;
            RGBColor(255, mix(230.0, 40.0, f), mix(80.0, 20.0, f))
        } else {
            let f = 2.0 * (t - 0.5);
            RGBColor(mix(255.0, 30.0, f), mix(40.0, 0.0, f), mix(20.0, 0.0, f))
        }
    };
    // White cells are the background: only the others are drawn.
    chart
        .draw_series(
            cells
                .iter()
                .filter(|(_, value)| *value >= low)
                .map(|(r, value)| {
                    Rectangle::new([(r[0], r[2]), (r[1], r[3])], shade(*value).filled())
                }),
        )
        .map_err(|e| error(&e))?;
    // The outline of the section.
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(x0, y0), (x1, y1)],
            BLACK.stroke_width(1),
        )))
        .map_err(|e| error(&e))?;
    root.present().map_err(|e| error(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_legend_goes_to_the_corner_without_data() {
        // GOAL: legends are placed off the data (issue 17). SETUP: a rising curve (empty upper
        //   left and lower right), a falling one, and a flat curve near the top.
        // REFERENCE: a corner the data leave empty.
        let rising: Vec<(f64, f64)> = (0..=20).map(|i| (i as f64, i as f64)).collect();
        assert!(matches!(
            emptiest_corner(&[&rising], (0.0, 20.0), (0.0, 20.0)),
            SeriesLabelPosition::UpperLeft | SeriesLabelPosition::LowerRight
        ));
        let falling: Vec<(f64, f64)> = (0..=20).map(|i| (i as f64, 20.0 - i as f64)).collect();
        assert!(matches!(
            emptiest_corner(&[&falling], (0.0, 20.0), (0.0, 20.0)),
            SeriesLabelPosition::UpperRight | SeriesLabelPosition::LowerLeft
        ));
        let flat: Vec<(f64, f64)> = (0..=20)
            .map(|i| (i as f64, 18.0 + 0.1 * i as f64))
            .collect();
        assert!(matches!(
            emptiest_corner(&[&flat], (0.0, 20.0), (0.0, 20.0)),
            SeriesLabelPosition::LowerRight | SeriesLabelPosition::LowerLeft
        ));
    }
}

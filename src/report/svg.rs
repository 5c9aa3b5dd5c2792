//! The report's figure: error against run time, log–log, one series per method, as SVG
//! (plotters).

use super::status;
use crate::solve::Method;
use crate::study::MeshPoint;

/// Error against run time, log–log, one series per method (plotters' SVG backend).
pub(super) fn svg_figure(points: &[MeshPoint], title: &str) -> String {
    use plotters::prelude::*;
    let series: Vec<(Method, Vec<(f64, f64)>)> = Method::ALL
        .into_iter()
        .map(|m| {
            let data = points
                .iter()
                .filter(|p| p.method == m && status(p).is_ok())
                .filter_map(|p| {
                    let e = p.error?.max_rel?;
                    let t = p.run_time.as_secs_f64();
                    (e > 0.0 && t > 0.0).then_some((t, e))
                })
                .collect();
            (m, data)
        })
        .filter(|(_, d): &(Method, Vec<(f64, f64)>)| !d.is_empty())
        .collect();
    let all: Vec<(f64, f64)> = series.iter().flat_map(|(_, d)| d.iter().copied()).collect();
    let bound = |f: fn(&(f64, f64)) -> f64| {
        let values: Vec<f64> = all.iter().map(f).collect();
        let low = values.iter().copied().fold(f64::INFINITY, f64::min);
        let high = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if low.is_finite() && high.is_finite() {
            (
                10f64.powf(low.log10().floor()),
                10f64.powf(high.log10().ceil()),
            )
        } else {
            (1e-6, 1.0)
        }
    };
    let (x, y) = (bound(|p| p.0), bound(|p| p.1));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 480)).into_drawing_area();
        let _ = root.fill(&WHITE);
        let built = ChartBuilder::on(&root)
            .caption(
                format!("{title}: error against run time"),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((x.0..x.1).log_scale(), (y.0..y.1).log_scale());
        if let Ok(mut chart) = built {
            let decade = |v: &f64| format!("1e{}", v.log10().round() as i32);
            let _ = chart
                .configure_mesh()
                .x_desc("run time [s]")
                .y_desc("max relative nodal error")
                .x_label_formatter(&decade)
                .y_label_formatter(&decade)
                .draw();
            const COLORS: [RGBColor; 6] = [
                RGBColor(0, 114, 178),
                RGBColor(0, 158, 115),
                RGBColor(213, 94, 0),
                RGBColor(204, 121, 167),
                RGBColor(86, 64, 0),
                RGBColor(90, 90, 90),
            ];
            for (method, data) in &series {
                let index = Method::ALL.iter().position(|m| m == method).unwrap_or(0);
                let color = COLORS[index % COLORS.len()].to_rgba();
                if let Ok(drawn) = chart.draw_series(
                    data.iter()
                        .map(move |&(t, e)| Circle::new((t, e), 4, color.filled())),
                ) {
                    drawn
                        .label(method.name())
                        .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
                }
            }
            let _ = chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .position(SeriesLabelPosition::UpperRight)
                .draw();
        }
        let _ = root.present();
    }
    svg
}

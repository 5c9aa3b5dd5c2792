//! `beamfric figure` and the report's SVG from the outside (issue 25): every figure parses as
//! XML, has one polyline per series with a vertex per point swept, axis names with units,
//! decade labels at their decades, text of slide size, and nothing outside its view box; the
//! ε figure's points are `sweep epsilon`'s numbers; existing files and unknown panels are
//! refused in words.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Output;

use crate::harness::process::{NO_COLOR, beamfric_with};

fn beamfric(args: &[&str]) -> Output {
    beamfric_with(args, NO_COLOR)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Small sweeps, so that the tests stay quick: the options of each panel.
fn quick_options(panel: &str) -> Vec<&'static str> {
    match panel {
        "eps-error" | "eps-cond" => vec!["--from", "1e-12", "--to", "1e-2", "--points", "6"],
        "error-time" => vec![
            "--from", "10", "--to", "300", "--points", "3", "--repeat", "1",
        ],
        _ => vec![],
    }
}

/// `beamfric figure PANEL --scene SCENE [extra] --out DIR/NAME.svg`: the SVG written.
fn figure(dir: &Path, panel: &str, scene: &str, extra: &[&str]) -> String {
    let out = dir.join(format!("{scene}-{panel}.svg"));
    let mut args = vec!["figure", panel, "--scene", scene];
    args.extend_from_slice(extra);
    args.extend(["--out", out.to_str().unwrap()]);
    let run = beamfric(&args);
    assert!(run.status.success(), "{args:?}: {}", stderr(&run));
    assert!(
        stderr(&run).contains(&format!("wrote {}", out.display())),
        "{}",
        stderr(&run)
    );
    std::fs::read_to_string(&out).unwrap()
}

/// A number from an attribute.
fn number(node: roxmltree::Node, name: &str) -> f64 {
    let text = node
        .attribute(name)
        .unwrap_or_else(|| panic!("{:?} has no {name}", node.tag_name().name()));
    text.parse()
        .unwrap_or_else(|_| panic!("{name}=\"{text}\" is not a number"))
}

/// The (x, y) pairs of a `points` attribute.
fn point_list(node: roxmltree::Node) -> Vec<(f64, f64)> {
    node.attribute("points")
        .unwrap()
        .split_whitespace()
        .map(|pair| {
            let (x, y) = pair.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

/// The rectangle an element covers, text by a conservative estimate (0.6 × font size per
/// character, the font size above the baseline and 0.3 of it below).
fn extent(node: roxmltree::Node) -> Option<[f64; 4]> {
    let span = |points: &[(f64, f64)]| {
        let xs = points.iter().map(|p| p.0);
        let ys = points.iter().map(|p| p.1);
        [
            xs.clone().fold(f64::INFINITY, f64::min),
            ys.clone().fold(f64::INFINITY, f64::min),
            xs.fold(f64::NEG_INFINITY, f64::max),
            ys.fold(f64::NEG_INFINITY, f64::max),
        ]
    };
    Some(match node.tag_name().name() {
        "rect" => {
            let (x, y) = (number(node, "x"), number(node, "y"));
            [x, y, x + number(node, "width"), y + number(node, "height")]
        }
        "line" => span(&[
            (number(node, "x1"), number(node, "y1")),
            (number(node, "x2"), number(node, "y2")),
        ]),
        "polyline" | "polygon" => span(&point_list(node)),
        "circle" => {
            let (x, y, r) = (number(node, "cx"), number(node, "cy"), number(node, "r"));
            [x - r, y - r, x + r, y + r]
        }
        "text" => {
            let size = number(node, "font-size");
            let width = node.text().unwrap_or("").chars().count() as f64 * 0.6 * size;
            let (x, y) = (number(node, "x"), number(node, "y"));
            let left = match node.attribute("text-anchor") {
                Some("middle") => x - width / 2.0,
                Some("end") => x - width,
                _ => x,
            };
            [left, y - size, left + width, y + 0.3 * size]
        }
        _ => return None,
    })
}

/// A decade label (`10⁻¹⁶`) or a linear one (`−0.005`, `4×10⁻⁶`) as the number it reads.
fn label_value(label: &str) -> f64 {
    let plain: String = label
        .chars()
        .map(|c| match c {
            '⁻' | '−' => '-',
            '⁰' => '0',
            '¹' => '1',
            '²' => '2',
            '³' => '3',
            '⁴' => '4',
            '⁵' => '5',
            '⁶' => '6',
            '⁷' => '7',
            '⁸' => '8',
            '⁹' => '9',
            c => c,
        })
        .collect();
    if let Some((mantissa, exponent)) = plain.split_once("×10") {
        return format!("{mantissa}e{exponent}").parse().unwrap();
    }
    let is_decade = label
        .strip_prefix("10")
        .is_some_and(|e| !e.is_empty() && e.chars().all(|c| !c.is_ascii_digit() && c != '.'));
    if is_decade {
        return format!("1e{}", plain.strip_prefix("10").unwrap())
            .parse()
            .unwrap();
    }
    plain.parse().unwrap_or_else(|_| panic!("label {label:?}"))
}

/// What a figure holds, by series: the polyline's vertices and the markers' data values.
#[derive(Debug, Default)]
struct SeriesSeen {
    vertices: Vec<(f64, f64)>,
    markers: Vec<(f64, f64)>,
}

/// Checks what every figure must satisfy, and returns its series by name.
fn check_figure(what: &str, svg: &str) -> BTreeMap<String, SeriesSeen> {
    let doc = roxmltree::Document::parse(svg).unwrap_or_else(|e| panic!("{what}: {e}"));
    let root = doc.root_element();
    let view: Vec<f64> = root
        .attribute("viewBox")
        .unwrap()
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(view[..2], [0.0, 0.0], "{what}");
    let (width, height) = (view[2], view[3]);
    assert!(
        (width / height - 16.0 / 9.0).abs() < 1e-9,
        "{what}: not 16:9"
    );
    let mut series: BTreeMap<String, SeriesSeen> = BTreeMap::new();
    let mut axis_names = Vec::new();
    for node in root.descendants().filter(|n| n.is_element()) {
        if let Some([x0, y0, x1, y1]) = extent(node) {
            let inside = x0 >= -1e-9 && y0 >= -1e-9 && x1 <= width + 1e-9 && y1 <= height + 1e-9;
            assert!(
                inside,
                "{what}: <{}> reaches [{x0}, {y0}] – [{x1}, {y1}], outside 0 0 {width} {height}: {:?}",
                node.tag_name().name(),
                node.text()
            );
        }
        let class = node.attribute("class").unwrap_or("");
        if node.tag_name().name() == "text" {
            assert!(number(node, "font-size") >= 19.0, "{what}: small text");
        }
        match class {
            "axis-name" => axis_names.push(node.text().unwrap().to_string()),
            "tick-label" => {
                let label = node.text().unwrap();
                assert_eq!(
                    label_value(label),
                    number(node, "data-value"),
                    "{what}: the label {label} is not its tick's value"
                );
            }
            "series-line" => {
                let name = node.attribute("data-series").unwrap().to_string();
                let seen = series.entry(name.clone()).or_default();
                assert!(seen.vertices.is_empty(), "{what}: two lines for {name}");
                seen.vertices = point_list(node);
            }
            "marker" => {
                let name = node.attribute("data-series").unwrap().to_string();
                let value = (number(node, "data-x"), number(node, "data-y"));
                series.entry(name).or_default().markers.push(value);
            }
            _ => {}
        }
    }
    assert_eq!(axis_names.len(), 2, "{what}: {axis_names:?}");
    for name in &axis_names {
        assert!(
            name.contains('[') && name.ends_with(']'),
            "{what}: the axis name {name:?} has no unit"
        );
    }
    for (name, seen) in &series {
        assert!(!seen.vertices.is_empty(), "{what}: {name} has no line");
        if !seen.markers.is_empty() {
            assert_eq!(seen.vertices.len(), seen.markers.len(), "{what}: {name}");
        }
    }
    series
}

/// The plot area's transform: pixel back to data value, per axis.
fn data_of(svg: &str, pixel: (f64, f64)) -> (f64, f64) {
    let doc = roxmltree::Document::parse(svg).unwrap();
    let area = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("plot-area"))
        .unwrap();
    let back = |axis: &str, fraction: f64| {
        let (low, high) = (
            number(area, &format!("data-{axis}-low")),
            number(area, &format!("data-{axis}-high")),
        );
        match area.attribute(format!("data-{axis}-scale").as_str()) {
            Some("log") => 10f64.powf(low.log10() + fraction * (high.log10() - low.log10())),
            _ => low + fraction * (high - low),
        }
    };
    let (x, y, w, h) = (
        number(area, "x"),
        number(area, "y"),
        number(area, "width"),
        number(area, "height"),
    );
    (
        back("x", (pixel.0 - x) / w),
        back("y", (y + h - pixel.1) / h),
    )
}

const PRESETS: [&str; 3] = ["benchmark-1", "benchmark-3", "modulus-contrast"];
const PANELS: [&str; 4] = ["deflection", "eps-error", "eps-cond", "error-time"];

#[test]
fn every_panel_of_three_presets_is_valid_svg_inside_its_view_box() {
    let dir = tempfile::tempdir().unwrap();
    for scene in PRESETS {
        for panel in PANELS {
            let svg = figure(dir.path(), panel, scene, &quick_options(panel));
            let what = format!("{scene} {panel}");
            let series = check_figure(&what, &svg);
            match panel {
                "deflection" => {
                    let (_, line) = series.iter().next().expect("the solution's line");
                    assert!(line.vertices.len() >= beamfric::figure::SAMPLES, "{what}");
                    let obstacles = svg.matches(r#"class="obstacle""#).count();
                    let expected = beamfric::scene::load(scene)
                        .unwrap()
                        .problem
                        .obstacles
                        .len();
                    assert_eq!(obstacles, expected, "{what}");
                }
                // The quick ε sweep: 6 values and the scene's ε.
                "eps-error" | "eps-cond" => {
                    assert!(!series.is_empty(), "{what}");
                    for (name, seen) in &series {
                        assert!(seen.markers.len() >= 6, "{what}: {name}");
                    }
                }
                _ => assert!(series.len() >= 3, "{what}: {:?}", series.keys()),
            }
            assert!(svg.contains(r#"class="current-rule""#) || panel == "deflection");
        }
    }
    // The stiff insert of modulus-contrast is a band under the axis, its E·J in the legend.
    let svg = std::fs::read_to_string(dir.path().join("modulus-contrast-deflection.svg")).unwrap();
    assert_eq!(svg.matches(r#"class="stiffness-band""#).count(), 3);
    assert!(svg.contains("EJ = 2.87e9 N m²"), "{svg}");
}

/// The CSV of a sweep, as rows of named fields.
fn csv_rows(text: &[u8]) -> Vec<BTreeMap<String, String>> {
    let mut reader = csv::Reader::from_reader(text);
    let headers = reader.headers().unwrap().clone();
    reader
        .records()
        .map(|r| {
            headers
                .iter()
                .map(String::from)
                .zip(r.unwrap().iter().map(String::from))
                .collect()
        })
        .collect()
}

#[test]
fn the_epsilon_figure_of_benchmark_1_is_sweep_epsilons_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = beamfric(&[
        "sweep",
        "epsilon",
        "--scene",
        "benchmark-1",
        "--format",
        "csv",
    ]);
    assert!(sweep.status.success(), "{}", stderr(&sweep));
    let rows = csv_rows(&sweep.stdout);
    assert_eq!(rows.len(), 33);
    for (panel, series_name, column) in [
        ("eps-error", "max rel. error", "max_rel"),
        ("eps-cond", "cond₂(Â)", "cond_max"),
    ] {
        let svg = figure(dir.path(), panel, "benchmark-1", &[]);
        let series = check_figure(panel, &svg);
        let seen = &series[series_name];
        let expected: Vec<(f64, f64)> = rows
            .iter()
            .map(|r| (r["epsilon"].parse().unwrap(), r[column].parse().unwrap()))
            .collect();
        // Every swept ε is in the figure with the same number (the scene's ε may be added).
        assert!(seen.markers.len() >= expected.len(), "{panel}");
        for (epsilon, value) in &expected {
            assert!(
                seen.markers.contains(&(*epsilon, *value)),
                "{panel}: ε = {epsilon}, {column} = {value} not in the figure: {:?}",
                seen.markers
            );
        }
        // The line's vertices are at those values too, through the axes' transform.
        for (vertex, marker) in seen.vertices.iter().zip(&seen.markers) {
            let (x, y) = data_of(&svg, *vertex);
            for (got, want) in [(x, marker.0), (y, marker.1)] {
                let decades = (got.log10() - want.log10()).abs();
                assert!(decades < 1e-3, "{panel}: {got} drawn for {want}");
            }
        }
    }
}

#[test]
fn the_error_figure_has_a_line_per_method_through_every_size() {
    let dir = tempfile::tempdir().unwrap();
    let range = [
        "--from", "10", "--to", "300", "--points", "3", "--repeat", "1",
    ];
    let mut args = vec![
        "sweep",
        "elements",
        "--scene",
        "benchmark-3",
        "--format",
        "csv",
    ];
    args.extend(range);
    let sweep = beamfric(&args);
    assert!(sweep.status.success(), "{}", stderr(&sweep));
    let mut extra = range.to_vec();
    extra.extend(["--against", "elements"]);
    let svg = figure(dir.path(), "error-time", "benchmark-3", &extra);
    let series = check_figure("error-time", &svg);
    let mut expected: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    for row in csv_rows(&sweep.stdout) {
        let error: f64 = match row["max_rel"].parse() {
            Ok(e) if row["status"] != "reference" && e > 0.0 => e,
            _ => continue,
        };
        let n: f64 = row["elements"].parse().unwrap();
        expected
            .entry(row["method"].clone())
            .or_default()
            .push((n, error));
    }
    assert!(expected.len() >= 3, "{expected:?}");
    assert_eq!(
        series.keys().collect::<Vec<_>>(),
        expected.keys().collect::<Vec<_>>()
    );
    for (method, points) in &expected {
        let seen = &series[method];
        assert!(seen.vertices.len() >= points.len(), "{method}");
        for point in points {
            assert!(seen.markers.contains(point), "{method}: {point:?}");
        }
    }
}

#[test]
fn figure_refuses_an_existing_file_an_unknown_panel_and_another_format() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("mine.svg");
    std::fs::write(&out, "mine").unwrap();
    let path = out.to_str().unwrap();
    let args = [
        "figure",
        "deflection",
        "--scene",
        "benchmark-1",
        "--out",
        path,
    ];
    let run = beamfric(&args);
    assert_eq!(run.status.code(), Some(2));
    let message = stderr(&run);
    assert!(
        message.contains(path) && message.contains("--force"),
        "{message}"
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "mine");
    let mut forced = args.to_vec();
    forced.push("--force");
    let run = beamfric(&forced);
    assert!(run.status.success(), "{}", stderr(&run));
    check_figure("forced", &std::fs::read_to_string(&out).unwrap());

    let run = beamfric(&["figure", "plot", "--out", "x.svg"]);
    assert_eq!(run.status.code(), Some(2));
    let message = stderr(&run);
    assert!(message.contains("'plot'"), "{message}");
    assert!(message.contains("eps-error"), "{message}");

    let jpeg = dir.path().join("figure.jpg");
    let run = beamfric(&["figure", "eps-error", "--out", jpeg.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(2));
    assert!(stderr(&run).contains(".svg"), "{}", stderr(&run));
    assert!(!jpeg.exists());

    // No run has no median: refused as `report` and `sweep mesh` refuse it (stop 58).
    let never = dir.path().join("never.svg");
    let never_path = never.to_str().unwrap();
    let run = beamfric(&["figure", "error-time", "--repeat", "0", "--out", never_path]);
    assert_eq!(run.status.code(), Some(2));
    let message = stderr(&run);
    assert!(
        message.contains("--repeat 0: must be from 1 to 100"),
        "{message}"
    );
    assert!(!never.exists());
}

/// `--out FILE.png`: the same figure rendered by resvg at 1920 × 1080 (where the system has
/// fonts; else refused in words and nothing written).
#[test]
fn figure_writes_a_png_of_the_same_figure() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("eps.PNG");
    let run = beamfric(&[
        "figure",
        "eps-error",
        "--scene",
        "benchmark-1",
        "--out",
        png.to_str().unwrap(),
    ]);
    if !run.status.success() {
        assert!(stderr(&run).contains("no fonts found"), "{}", stderr(&run));
        assert!(!png.exists());
        return;
    }
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert_eq!((width, height), (1920, 1080));
    assert!(
        bytes.len() > 20_000,
        "{} bytes: a near-empty picture",
        bytes.len()
    );
}

#[test]
fn the_reports_figure_passes_the_same_checks() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let run = beamfric(&[
        "report",
        "--scene",
        "benchmark-1",
        "--out",
        out.to_str().unwrap(),
        "--from",
        "10",
        "--to",
        "300",
        "--points",
        "3",
        "--repeat",
        "1",
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let svg = std::fs::read_to_string(out.join("error-vs-time.svg")).unwrap();
    let series = check_figure("report", &svg);
    assert!(series.len() >= 3, "{:?}", series.keys());
    for (method, seen) in &series {
        assert!(seen.markers.len() >= 2, "{method}");
    }
    // Against run time n is on no axis: one method's points are labelled with their sizes,
    // the first as `n = 10`.
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let sizes: Vec<(String, String)> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("n-label"))
        .map(|n| {
            (
                n.attribute("data-n").unwrap().into(),
                n.text().unwrap().into(),
            )
        })
        .collect();
    assert_eq!(sizes.len(), 3, "{sizes:?}");
    assert_eq!(sizes[0], ("10".to_string(), "n = 10".to_string()));
    assert!(sizes[1..].iter().all(|(n, text)| n == text), "{sizes:?}");
}

#[test]
fn the_figure_module_uses_no_explorer_server_or_command_line() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/figure");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        for forbidden in ["crate::tui", "crate::serve", "crate::cli", "super::super"] {
            assert!(
                !text.contains(forbidden),
                "{} uses {forbidden}",
                path.display()
            );
        }
    }
}

/// The explorer's `e` writes the focused panel as `beamfric figure` does, byte for byte (the
/// same sweeps, the same drawing), next to the scene's save name and never over a file: a
/// second `e` writes `-2`; a render without `--allow-save` writes nothing and says so.
#[test]
fn the_explorers_e_writes_the_same_figure_as_the_command() {
    let dir = tempfile::tempdir().unwrap();
    let allow = dir.path().to_str().unwrap();
    let run = beamfric(&[
        "render",
        "--scene",
        "benchmark-1",
        "--size",
        "80x24",
        "--keys",
        "e Tab e Tab e Tab e e",
        "--allow-save",
        allow,
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let frame = String::from_utf8_lossy(&run.stdout);
    assert!(
        frame.contains("figure saved: benchmark-1-error-time-2.svg"),
        "{frame}"
    );
    let command = tempfile::tempdir().unwrap();
    for panel in PANELS {
        let exported = std::fs::read_to_string(dir.path().join(format!("benchmark-1-{panel}.svg")))
            .unwrap_or_else(|e| panic!("{panel}: {e}"));
        check_figure(panel, &exported);
        let extra: &[&str] = if panel == "error-time" {
            &["--against", "elements"]
        } else {
            &[]
        };
        assert_eq!(
            exported,
            figure(command.path(), panel, "benchmark-1", extra),
            "{panel}"
        );
    }
    assert_eq!(
        std::fs::read(dir.path().join("benchmark-1-error-time-2.svg")).unwrap(),
        std::fs::read(dir.path().join("benchmark-1-error-time.svg")).unwrap()
    );
    // Without --allow-save nothing is written, in words.
    let run = beamfric(&["render", "--scene", "benchmark-1", "--keys", "e"]);
    let frame = String::from_utf8_lossy(&run.stdout);
    assert!(
        frame.contains("figure not written: benchmark-1-deflection.svg (a render writes no"),
        "{frame}"
    );
}

//! A scene's own text in every output (issue 22): a title or a description may hold control
//! characters (the scene file format allows any string), and none of them reaches a file or a
//! terminal raw — report.md, the CSV files, the SVG figure, the JSON and the table of `solve`,
//! and the explorer's frame. Each shows them as `\u{..}` escapes
//! (`beamfric::format::printable`), JSON as its own `\u001b` escapes (serde_json's below
//! U+0020, `beamfric::output::json_text`'s for DEL and C1); report.md writes `&`, `<` and `>`
//! in them as HTML entities.

use std::path::Path;

use beamfric::scene::{Scene, preset};

use crate::harness::process::beamfric;

/// A red-colouring escape sequence, a bell, a new line and a C1 control (CSI) in the title; a
/// sequence that retitles the terminal and a C1 control in the description.
const TITLE: &str = "Red \x1b[31mtitle\x07\nsecond line\u{9b}";
const DESCRIPTION: &str = "retitled \x1b]0;pwned\x07 and \u{9b}2J cleared";

/// Benchmark 1 with [`TITLE`] and [`DESCRIPTION`], written to `dir/hostile.toml`.
fn hostile_scene(dir: &Path) -> String {
    let mut scene = Scene::from_toml(preset("benchmark-1").unwrap().text, "b1").unwrap();
    scene.title = TITLE.into();
    scene.description = DESCRIPTION.into();
    let path = dir.join("hostile.toml");
    std::fs::write(&path, scene.to_toml()).unwrap();
    // The format allows it: the file loads, with the title as written.
    let loaded = beamfric::scene::load(path.to_str().unwrap()).unwrap();
    assert_eq!(loaded.scene.title, TITLE);
    path.to_str().unwrap().to_string()
}

/// The control characters of `text` other than the line breaks of its own layout.
fn raw_controls(text: &str) -> Vec<char> {
    text.chars()
        .filter(|c| c.is_control() && *c != '\n')
        .collect()
}

/// `text` holds no raw control character, and does hold the escaped ESC of the title.
fn escaped(what: &str, text: &str) {
    assert_eq!(raw_controls(text), Vec::<char>::new(), "{what}:\n{text:?}");
    assert!(!text.contains("\x07\n"), "{what}");
    assert!(
        text.contains(r"\u{1b}[31mtitle\u{7}\u{a}second line\u{9b}"),
        "{what}:\n{text}"
    );
}

/// `beamfric report` of `scene` into `out_dir` on two mesh sizes up to 100, one run each:
/// its report.md.
fn small_report(scene: &str, out_dir: &Path) -> String {
    let out = beamfric(&[
        "report",
        "--scene",
        scene,
        "--out",
        out_dir.to_str().unwrap(),
        "--to",
        "100",
        "--points",
        "2",
        "--repeat",
        "1",
    ]);
    assert!(out.status.success(), "{out:?}");
    std::fs::read_to_string(out_dir.join("report.md")).unwrap()
}

#[test]
fn a_report_escapes_control_characters_in_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let scene = hostile_scene(dir.path());
    let out_dir = dir.path().join("report");
    let markdown = small_report(&scene, &out_dir);
    escaped("report.md", &markdown);
    assert!(
        markdown.contains(r"retitled \u{1b}]0;pwned\u{7} and \u{9b}2J cleared"),
        "{markdown}"
    );
    let svg = std::fs::read_to_string(out_dir.join("error-vs-time.svg")).unwrap();
    escaped("error-vs-time.svg", &svg);
    // The CSV files hold no scene text, and no control character either.
    for csv in ["mesh-sweep.csv", "epsilon-sweep.csv"] {
        let text = std::fs::read_to_string(out_dir.join(csv)).unwrap();
        assert_eq!(raw_controls(&text), Vec::<char>::new(), "{csv}");
    }
}

#[test]
fn solve_escapes_the_title_in_its_table_and_json_escapes_it_its_own_way() {
    let dir = tempfile::tempdir().unwrap();
    let scene = hostile_scene(dir.path());
    let out = beamfric(&["solve", "--scene", &scene]);
    assert!(out.status.success(), "{out:?}");
    escaped("the table", &String::from_utf8(out.stdout).unwrap());

    let out = beamfric(&["solve", "--scene", &scene, "--format", "json"]);
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(raw_controls(&text), Vec::<char>::new(), "{text}");
    assert!(
        text.contains(r"\u001b[31mtitle\u0007\nsecond line\u009b"),
        "{text}"
    );
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["title"], TITLE, "JSON keeps the title exactly");
}

#[test]
fn the_explorer_shows_control_characters_as_escapes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = hostile_scene(dir.path());
    // The title line and the description line, then the help with the description in full.
    for keys in ["", "?"] {
        let out = beamfric(&[
            "render", "--scene", &scene, "--size", "200x50", "--keys", keys,
        ]);
        assert!(out.status.success(), "{out:?}");
        let frame = String::from_utf8(out.stdout).unwrap();
        assert_eq!(raw_controls(&frame), Vec::<char>::new(), "{frame}");
        assert!(frame.contains(r"\u{1b}]0;pwned\u{7}"), "{keys:?}:\n{frame}");
    }
    let out = beamfric(&["render", "--scene", &scene, "--size", "200x50"]);
    escaped("the frame", &String::from_utf8(out.stdout).unwrap());
}

#[test]
fn a_report_writes_html_in_scene_text_as_text() {
    // Stop 58's hostile pass: report.md copied `<img src=x>` from a title verbatim, HTML that
    // a Markdown viewer would render (and some would run).
    let dir = tempfile::tempdir().unwrap();
    let mut scene = Scene::from_toml(preset("benchmark-1").unwrap().text, "b1").unwrap();
    scene.title = "<img src=x onerror=alert(1)> & co".into();
    scene.description = "a <script>b</script> c".into();
    let path = dir.path().join("html.toml");
    std::fs::write(&path, scene.to_toml()).unwrap();
    let markdown = small_report(path.to_str().unwrap(), &dir.path().join("report"));
    assert!(
        markdown.contains("# Error against run time: &lt;img src=x onerror=alert(1)&gt; &amp; co"),
        "{markdown}"
    );
    assert!(
        markdown.contains("a &lt;script&gt;b&lt;/script&gt; c"),
        "{markdown}"
    );
    assert!(!markdown.contains("<img") && !markdown.contains("<script"));
}

#[test]
fn a_figure_writes_bidirectional_controls_as_escapes() {
    // Stop 58's hostile pass: `figure` wrote a right-to-left override (U+202E) of a title raw
    // into the SVG, where a viewer shows the rest of the title reversed; report's figure and
    // every other output escaped it.
    let dir = tempfile::tempdir().unwrap();
    let mut scene = Scene::from_toml(preset("benchmark-1").unwrap().text, "b1").unwrap();
    scene.title = "left \u{202e}thgir\u{2066} end".into();
    let path = dir.path().join("bidi.toml");
    std::fs::write(&path, scene.to_toml()).unwrap();
    let svg_of = |extra: &[&str]| {
        let out_path = dir.path().join("figure.svg");
        let out_file = out_path.to_str().unwrap();
        let mut args = vec!["figure", "deflection", "--scene"];
        args.extend([path.to_str().unwrap(), "--out", out_file, "--force"]);
        args.extend(extra);
        let out = beamfric(&args);
        assert!(out.status.success(), "{out:?}");
        std::fs::read_to_string(&out_path).unwrap()
    };
    let svg = svg_of(&[]);
    assert!(svg.contains(r"left \u{202e}thgir\u{2066} end"), "{svg}");
    // A title of one's own: a control character is a blank, a bidirectional one escaped.
    let svg = svg_of(&["--title", "a\u{1b}b\u{202e}c"]);
    assert!(svg.contains(r"<title>a b\u{202e}c</title>"), "{svg}");
    for text in [svg_of(&[]), svg] {
        let raw = |c: char| c != '\n' && beamfric::format::acts_on_text(c);
        assert!(!text.contains(raw), "{text}");
    }
}

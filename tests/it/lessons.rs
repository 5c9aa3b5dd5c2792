//! Lessons (issue 23): every step of every shipped lesson rendered at 80×24 and 120×40 (insta
//! snapshots, with the step line, the whole caption and the status figures on screen), a
//! malformed lesson rejected with its file, step and field named, `render --lesson --step`,
//! stepping forward and back in a pty (a step's changes kept for the return, quitting asks),
//! and a class: followers see the step and its caption, a fork keeps the caption it forked at.

use std::path::Path;
use std::sync::Arc;

use beamfric::lesson::{CAPTION_LINES, Lesson, LessonError, read_lesson, wrap};
use beamfric::plot::{Look, buffer_to_text};
use beamfric::tui::state::LessonPlace;
use beamfric::tui::{RenderOptions, draw_to_buffer, prepare};

use crate::harness::process::beamfric;
use crate::harness::pty::PtyProcess;

/// The lessons shipped in `lessons/`.
const SHIPPED: [&str; 4] = [
    "lessons/regularisation.toml",
    "lessons/dual-and-fine-meshes.toml",
    "lessons/stiff-and-extreme.toml",
    "lessons/method-at-work.toml",
];

fn shipped(file: &str) -> Arc<Lesson> {
    Arc::new(read_lesson(Path::new(file)).unwrap_or_else(|e| panic!("{e}")))
}

/// The frame of step `step` (from 0) at `width`×`height`, plain text.
fn step_frame(lesson: &Arc<Lesson>, step: usize, (width, height): (u16, u16)) -> String {
    let place = LessonPlace {
        lesson: Arc::clone(lesson),
        step,
    };
    let options = RenderOptions {
        width,
        height,
        look: Look {
            ascii: false,
            color: false,
        },
        palette: Default::default(),
        markers: Default::default(),
        timings: false,
        allow_save: None,
        lesson: Some(place.clone()),
    };
    let app = prepare(place.current().scene.clone(), &[], options).unwrap();
    buffer_to_text(&draw_to_buffer(&app, width, height), false)
}

#[test]
fn every_step_of_every_shipped_lesson_at_80x24_and_120x40() {
    for file in SHIPPED {
        let lesson = shipped(file);
        let stem = Path::new(file).file_stem().unwrap().to_string_lossy();
        let count = lesson.steps.len();
        assert!((5..=8).contains(&count), "{file}: {count} steps");
        for (index, step) in lesson.steps.iter().enumerate() {
            for size in [(80, 24), (120, 40)] {
                let text = step_frame(&lesson, index, size);
                let label = format!("lesson-{stem}-step-{}-{}x{}", index + 1, size.0, size.1);
                // The step line, and the whole caption as the strip wraps it.
                let step_line = format!("step {}/{count}: {}", index + 1, step.title);
                assert!(
                    text.contains(&step_line),
                    "{label}: no {step_line:?}\n{text}"
                );
                let width = usize::from(size.0) - 2;
                let caption = wrap(&step.caption, width);
                assert!(caption.len() <= CAPTION_LINES, "{label}");
                for line in &caption {
                    assert!(
                        text.contains(line.as_str()),
                        "{label}: {line:?} cut\n{text}"
                    );
                }
                // The status keeps the method and its figures.
                let method = step.scene.scene.solver.method.name();
                let status = text.lines().rev().nth(3).unwrap_or_default();
                assert!(status.starts_with(method), "{label}: status {status:?}");
                assert!(!text.contains("NaN"), "{label}\n{text}");
                insta::assert_snapshot!(label, text);
            }
        }
    }
}

#[test]
fn a_shipped_lessons_steps_are_its_own_scenes_and_settings() {
    let lesson = shipped("lessons/dual-and-fine-meshes.toml");
    // A step without a scene goes on from the one before, with its own settings.
    let elements: Vec<usize> = lesson
        .steps
        .iter()
        .map(|s| s.scene.scene.mesh.elements)
        .collect();
    assert_eq!(elements.iter().max(), Some(&200_000), "{elements:?}");
    assert!(
        lesson
            .steps
            .iter()
            .any(|s| s.scene.scene.solver.method == beamfric::model::Method::Condensed)
    );
}

/// A malformed lesson: its text, and what the error must name.
struct Malformed {
    name: &'static str,
    text: &'static str,
    step: Option<usize>,
    field: &'static str,
    rule: &'static str,
}

const STEP_ONE: &str =
    "title = \"L\"\n[[step]]\ntitle = \"one\"\npreset = \"benchmark-1\"\ncaption = \"first\"\n";

fn malformed() -> Vec<Malformed> {
    let second = |rest: &'static str| -> &'static str {
        Box::leak(
            format!("{STEP_ONE}[[step]]\ntitle = \"two\"\ncaption = \"second\"\n{rest}")
                .into_boxed_str(),
        )
    };
    vec![
        Malformed {
            name: "unknown-field",
            text: second("colour = \"red\"\n"),
            step: Some(2),
            field: "colour",
            rule: "unknown field",
        },
        Malformed {
            name: "bad-method",
            text: second("method = \"magic\"\n"),
            step: Some(2),
            field: "method",
            rule: "magic",
        },
        Malformed {
            name: "negative-epsilon",
            text: second("epsilon = -1.0\n"),
            step: Some(2),
            field: "epsilon",
            rule: "greater than zero",
        },
        Malformed {
            name: "no-elements",
            text: second("elements = 0\n"),
            step: Some(2),
            field: "elements",
            rule: "between 1 and",
        },
        Malformed {
            name: "focus-not-shown",
            text: second("panels = [\"deflection\"]\nfocus = \"eps-cond\"\n"),
            step: Some(2),
            field: "focus",
            rule: "one of the step's panels (deflection)",
        },
        Malformed {
            name: "first-step-without-scene",
            text: "title = \"L\"\n[[step]]\ntitle = \"one\"\ncaption = \"x\"\n",
            step: Some(1),
            field: "preset",
            rule: "the first step must name its scene",
        },
        Malformed {
            name: "preset-and-scene",
            text: "title = \"L\"\n[[step]]\ntitle = \"one\"\npreset = \"benchmark-1\"\nscene = \"a.toml\"\ncaption = \"x\"\n",
            step: Some(1),
            field: "preset, scene",
            rule: "not both",
        },
        Malformed {
            name: "unknown-preset",
            text: "title = \"L\"\n[[step]]\ntitle = \"one\"\npreset = \"benchmark-9\"\ncaption = \"x\"\n",
            step: Some(1),
            field: "preset",
            rule: "no such preset",
        },
        Malformed {
            name: "missing-scene-file",
            text: "title = \"L\"\n[[step]]\ntitle = \"one\"\nscene = \"nowhere.toml\"\ncaption = \"x\"\n",
            step: Some(1),
            field: "scene",
            rule: "relative to the lesson's folder",
        },
        Malformed {
            name: "invalid-scene-file",
            text: "title = \"L\"\n[[step]]\ntitle = \"one\"\nscene = \"outside.toml\"\ncaption = \"x\"\n",
            step: Some(1),
            field: "obstacle",
            rule: "inside",
        },
        Malformed {
            name: "caption-too-long",
            text: second(""),
            step: Some(3),
            field: "caption",
            rule: "at most 3 fit",
        },
        Malformed {
            name: "missing-caption",
            text: second("[[step]]\ntitle = \"three\"\n"),
            step: Some(3),
            field: "",
            rule: "missing field `caption`",
        },
        Malformed {
            name: "no-steps",
            text: "title = \"L\"\n",
            step: None,
            field: "step",
            rule: "at least one [[step]]",
        },
        Malformed {
            name: "empty-title",
            text: "title = \" \"\n[[step]]\ntitle = \"one\"\npreset = \"benchmark-1\"\ncaption = \"x\"\n",
            step: None,
            field: "title",
            rule: "must not be empty",
        },
        Malformed {
            name: "syntax",
            text: second("[[step]]\ntitle = \"three\ncaption = \"x\"\n"),
            step: Some(3),
            field: "line",
            rule: "",
        },
    ]
}

#[test]
fn malformed_lessons_are_rejected_with_file_step_field_and_rule() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("outside.toml"),
        "[beam]\nlength = 1.0\nyoung = 2e11\nsection = { shape = \"circle\", radius = 0.01 }\n\
         [load]\nf0 = 1.0\n[[obstacle]]\nx = 1.5\nsliding = 1.0\nswivel = 1.0\n",
    )
    .unwrap();
    let long_caption = "word ".repeat(60);
    let cases = malformed();
    assert!(cases.len() >= 10);
    for case in cases {
        let path = dir.path().join(format!("{}.toml", case.name));
        let text = if case.name == "caption-too-long" {
            format!(
                "{}[[step]]\ntitle = \"three\"\ncaption = \"{long_caption}\"\n",
                case.text
            )
        } else {
            case.text.to_string()
        };
        std::fs::write(&path, text).unwrap();
        let error: LessonError = read_lesson(&path).expect_err(case.name);
        let message = error.to_string();
        assert_eq!(error.file, path.display().to_string(), "{message}");
        assert_eq!(error.step, case.step, "{}: {message}", case.name);
        assert!(error.field.contains(case.field), "{}: {message}", case.name);
        assert!(error.rule.contains(case.rule), "{}: {message}", case.name);
        assert!(
            message.starts_with(&path.display().to_string()),
            "{message}"
        );
        if let Some(step) = case.step {
            assert!(message.contains(&format!("step {step}: ")), "{message}");
        }
    }
}

#[test]
fn render_takes_a_lesson_step_and_refuses_a_bad_one_by_name() {
    let out = beamfric(&[
        "render",
        "--lesson",
        "lessons/regularisation.toml",
        "--step",
        "3",
        "--size",
        "80x24",
    ]);
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("step 3/"), "{text}");
    // Beyond the last step, and without a lesson.
    let out = beamfric(&[
        "render",
        "--lesson",
        "lessons/regularisation.toml",
        "--step",
        "99",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--step 99: lessons/regularisation.toml has"),
        "{stderr}"
    );
    let out = beamfric(&["render", "--lesson", SHIPPED[0], "--step", "0"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--step 0: ") && stderr.contains("counted from 1"),
        "{stderr}"
    );
    let out = beamfric(&["render", "--step", "2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--lesson"));
    // A malformed lesson: exit status 2 and one line naming the file, the step and the field.
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, malformed()[2].text).unwrap();
    let out = beamfric(&["render", "--lesson", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!("{}: step 2: epsilon: = -1", bad.display())),
        "{stderr}"
    );
}

#[test]
fn the_shipped_lessons_step_forward_and_back_in_a_pty() {
    for file in SHIPPED {
        let count = shipped(file).steps.len();
        let mut explorer = PtyProcess::start(&["--lesson", file], &[], (80, 24));
        explorer.wait_for_screen(&format!("step 1/{count}:"));
        for step in 2..=count {
            explorer.type_bytes(if step % 2 == 0 { b" " } else { b"n" });
            explorer.wait_for_screen(&format!("step {step}/{count}:"));
        }
        explorer.type_bytes(b" ");
        explorer.wait_for_screen("the last step");
        for step in (1..count).rev() {
            explorer.type_bytes(if step % 2 == 0 { b"\x7f" } else { b"N" });
            explorer.wait_for_screen(&format!("step {step}/{count}:"));
        }
        explorer.type_bytes(b"q");
        let status = explorer.exit();
        assert_eq!(status.code(), Some(0), "{file}: {status:?}");
    }
}

#[test]
fn a_steps_changes_are_kept_for_the_return_and_quitting_asks_for_them() {
    let mut explorer = PtyProcess::start(&["--lesson", SHIPPED[0]], &[], (80, 24));
    explorer.wait_for_screen("step 1/");
    // Raise the load a coarse step, step on and come back: the change is there.
    explorer.type_bytes(b"]");
    explorer.wait_for_screen("5.0e5 N/m");
    explorer.type_bytes(b" ");
    explorer.wait_for_screen("step 2/");
    assert!(!explorer.screen().contains("5.0e5 N/m"));
    explorer.type_bytes(b"\x7f");
    explorer.wait_for_screen("your changes to this step are back");
    explorer.wait_for_screen("5.0e5 N/m");
    // Away from it again, quitting names the changed step.
    explorer.type_bytes(b" ");
    explorer.wait_for_screen("step 2/");
    explorer.type_bytes(b"q");
    explorer.wait_for_screen("step 1 changed too");
    explorer.type_bytes(b"y");
    assert_eq!(explorer.exit().code(), Some(0));
}

#[cfg(unix)]
#[test]
fn followers_see_the_step_and_caption_and_a_fork_keeps_the_one_it_forked_at() {
    use crate::harness::lecture::{past_the_join_screen, present};
    use crate::harness::ssh::{Explorer, logged_in_as, runtime};

    let dir = tempfile::tempdir().unwrap();
    let lesson = shipped(SHIPPED[0]);
    let count = lesson.steps.len();
    let mut lecturer = present(dir.path(), &["--lesson", SHIPPED[0]], (80, 24));
    let (_, address) = past_the_join_screen(&mut lecturer);
    lecturer.wait_for_screen(&format!("step 1/{count}:"));
    let caption_line = |step: usize| wrap(&lesson.steps[step].caption, 78)[0].clone();
    runtime().block_on(async {
        let alice = logged_in_as(address, "alice").await;
        let mut student = Explorer::open(&alice, (80, 24), &[]).await;
        student.wait_for(&format!("step 1/{count}:")).await;
        lecturer.wait_for_screen("presenting · 1 follow · 1 student");
        // The lecturer steps on: the student sees the step and its caption.
        lecturer.type_bytes(b" ");
        student.wait_for(&format!("step 2/{count}:")).await;
        student.wait_for(&caption_line(1)).await;
        // The keys the caption names work once forked, and the step line says so.
        student.wait_for("· f: try the keys yourself").await;
        // A following student's Space does not step the class.
        student.send(b" ").await;
        student.wait_for("f to explore on your own").await;
        // Forked, the student keeps step 2 and its caption while the lecturer goes on.
        student.send(b"f").await;
        student.wait_for("own exploration").await;
        lecturer.type_bytes(b" ");
        lecturer.wait_for_screen(&format!("step 3/{count}:"));
        student.send(b"n").await;
        student
            .wait_for("the presenter steps through the lesson")
            .await;
        let screen = student.text();
        assert!(screen.contains(&format!("step 2/{count}:")), "{screen}");
        assert!(screen.contains(&caption_line(1)), "{screen}");
        assert!(!screen.contains(&format!("step 3/{count}:")), "{screen}");
        assert!(!screen.contains("try the keys yourself"), "{screen}");
        // Rejoining shows the lecturer's step.
        student.send(b"F").await;
        student.wait_for(&format!("step 3/{count}:")).await;
        student.wait_for(&caption_line(2)).await;
        // The class ends while the student is connected.
        lecturer.type_bytes(b"q");
        lecturer.wait_for_screen("1 student: end the class?");
        lecturer.type_bytes(b"y");
        student
            .wait_for("The class was ended by the lecturer")
            .await;
    });
    assert_eq!(lecturer.exit().code(), Some(0));
}

#[test]
fn a_served_session_steps_its_own_lesson_capped_at_the_servers_mesh_limit() {
    use beamfric::tui::state::{App, Options};
    use beamfric::tui::update::{Msg, update};

    let lesson = shipped("lessons/dual-and-fine-meshes.toml");
    let place = LessonPlace {
        lesson: Arc::clone(&lesson),
        step: 1,
    };
    let options = Options {
        max_elements: Some(100_000),
        lesson: Some(place.clone()),
        ..Options::new(Look {
            ascii: false,
            color: false,
        })
    };
    let mut app = App::new(place.current().scene.clone(), options).unwrap();
    // Step 3 asks for 2·10⁵ elements: shown at the limit, with a note, and usable.
    update(
        &mut app,
        Msg::Key(beamfric::tui::input::keys::Key::Char(' ')),
    );
    assert_eq!(app.exploration.lesson.as_ref().map(|p| p.step), Some(2));
    assert_eq!(app.scene().mesh.elements, 100_000);
    let note = app.message.clone().unwrap_or_default();
    assert!(
        note.contains("asks for n = 200000") && note.contains("100000"),
        "{note}"
    );
    assert!(
        !app.modified(),
        "the capped step is the step as shown, nothing to lose"
    );
    // Back and on again: nothing was changed, so nothing is kept for the step.
    update(
        &mut app,
        Msg::Key(beamfric::tui::input::keys::Key::Backspace),
    );
    assert_eq!(app.exploration.lesson.as_ref().map(|p| p.step), Some(1));
    assert!(app.step_edits.is_empty(), "{:?}", app.step_edits.keys());
}

#[test]
fn a_lessons_errors_are_one_escaped_line_with_columns_in_characters() {
    let dir = tempfile::tempdir().unwrap();
    // A field name with an escape sequence and a newline in it: quoted escaped, one line.
    let path = dir.path().join("escape.toml");
    std::fs::write(
        &path,
        format!("{STEP_ONE}\"\\u001b]0;PWNED\\u0007\\u001b[2J\\nx\" = 1\n"),
    )
    .unwrap();
    let message = read_lesson(&path).unwrap_err().to_string();
    assert!(!message.contains(|c: char| c.is_control()), "{message:?}");
    assert!(message.contains("\\u{1b}"), "{message}");
    // A column after ε counts characters (ε is two bytes).
    let path = dir.path().join("column.toml");
    std::fs::write(
        &path,
        "title = \"L\"\n[[step]]\ntitle = \"ε ε ε\"\npreset = \"benchmark-1\"\ncaption = \"ε ε ε ε ε ε \\q\"\n",
    )
    .unwrap();
    let error = read_lesson(&path).unwrap_err();
    assert!(error.field.contains("line 5, column 25"), "{error}"); // 31 in bytes
    // Titles and captions are measured in columns: 26 wide characters are 52.
    let path = dir.path().join("wide.toml");
    let wide = "字".repeat(26);
    std::fs::write(
        &path,
        format!("title = \"L\"\n[[step]]\ntitle = \"{wide}\"\npreset = \"benchmark-1\"\ncaption = \"x\"\n"),
    )
    .unwrap();
    let error = read_lesson(&path).unwrap_err();
    assert!(error.rule.contains("takes 52 columns"), "{error}");
    // CLI: exit status 2, one line.
    let out = beamfric(&[
        "render",
        "--lesson",
        dir.path().join("escape.toml").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.lines().count(), 1, "{stderr:?}");
    assert!(
        !stderr.trim_end().contains(|c: char| c.is_control()),
        "{stderr:?}"
    );
}

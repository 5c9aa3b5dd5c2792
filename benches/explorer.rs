//! One keystroke of the explorer (issue 3): apply the key, re-solve, draw the frame into a
//! 120×40 TestBackend — the work done before the next frame appears. Background sweeps are
//! excluded (they run on the worker thread; the panels say "computing" meanwhile). Also the
//! cost of drawing a frame whose every panel has its data.

use beamfric::plot::Look;
use beamfric::scene::{Scene, preset};
use beamfric::tui::input::keymap::Action;
use beamfric::tui::state::{App, Options};
use beamfric::tui::update::{Msg, update};
use beamfric::tui::{finish_sweeps, settle, view};
use criterion::{Criterion, criterion_group, criterion_main};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

fn app(elements: usize) -> App {
    let mut scene = Scene::from_toml(preset("benchmark-1").unwrap().text, "b1").unwrap();
    scene.mesh.elements = elements;
    let look = Look {
        ascii: false,
        color: true,
    };
    App::new(
        beamfric::scene::LoadedScene::new(
            scene,
            beamfric::scene::SceneSource::Preset("benchmark-1"),
        )
        .unwrap(),
        Options {
            show_timings: true,
            ..Options::new(look)
        },
    )
    .unwrap()
}

fn keystroke(c: &mut Criterion) {
    let mut group = c.benchmark_group("keystroke-120x40");
    for (label, elements) in [("n=20", 20), ("n=1e4", 10_000)] {
        let mut app = app(elements);
        update(&mut app, Msg::Resize(120, 40));
        let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
        let mut up = true;
        group.bench_function(label, |b| {
            b.iter(|| {
                // The load f0 one fine step up, then down again: a re-solve every time.
                let action = if up {
                    Action::Increase { coarse: false }
                } else {
                    Action::Decrease { coarse: false }
                };
                up = !up;
                update(&mut app, Msg::Action(action));
                settle(&mut app);
                terminal.draw(|frame| view::draw(frame, &app)).unwrap();
            })
        });
    }
    group.finish();
}

fn full_frame(c: &mut Criterion) {
    let mut app = app(20);
    update(&mut app, Msg::Resize(120, 40));
    settle(&mut app);
    finish_sweeps(&mut app);
    let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
    c.bench_function("draw-120x40-all-panels-ready", |b| {
        b.iter(|| {
            terminal.draw(|frame| view::draw(frame, &app)).unwrap();
        })
    });
}

criterion_group!(benches, keystroke, full_frame);
criterion_main!(benches);

//! The explorer's UI thread per key, as the interactive event loop runs it (issue 11): apply
//! the key (no solve: that is the worker's) and draw the next frame, with the previous result
//! on screen at n up to 10⁷ for every method. Prints the longest and the median stall per
//! (n, method), then the time from a key to the frame with its solution at n = 10⁶
//! (flexibility), through the real solver worker, on Benchmark 1 (the closed form grades the
//! answer) and on Benchmark 2 (no closed form: the `condensed` reference grades it and is the
//! chart's reference curve). A measured harness, not a test: `cargo bench --bench ui_stall`
//! (release build).

use std::sync::mpsc::channel;
use std::time::{Duration, Instant};

use beamfric::plot::Look;
use beamfric::scene::{LoadedScene, ObstacleSpec, Scene, SceneSource, preset};
use beamfric::solve::Method;
use beamfric::tui::input::keymap::Action;
use beamfric::tui::jobs::solve::SolveRequest;
use beamfric::tui::runtime::worker::{Worker, WorkerOptions};
use beamfric::tui::state::{App, Options};
use beamfric::tui::update::{Msg, update};
use beamfric::tui::{settle, view};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

const KEYS: usize = 40;

fn app(elements: usize, method: Method) -> App {
    app_on("benchmark-1", elements, method)
}

fn app_on(name: &'static str, elements: usize, method: Method) -> App {
    let mut scene = Scene::from_toml(preset(name).unwrap().text, name).unwrap();
    scene.mesh.elements = elements;
    scene.solver.method = method;
    let look = Look {
        ascii: false,
        color: true,
    };
    let loaded = LoadedScene::new(scene, SceneSource::Preset(name)).unwrap();
    let options = Options {
        show_timings: true,
        ..Options::new(look)
    };
    App::new(loaded, options).unwrap()
}

/// The load f0 one fine step up, then down: a change of the scene every key.
fn key(i: usize) -> Msg {
    Msg::Action(if i.is_multiple_of(2) {
        Action::Increase { coarse: false }
    } else {
        Action::Decrease { coarse: false }
    })
}

fn main() {
    // `cargo bench` passes `--bench`; `-- many` measures only the keys at many obstacles.
    if std::env::args().any(|a| a == "many") {
        keys_at_many_obstacles(4000);
        return;
    }
    let sizes = [20, 10_000, 1_000_000, 10_000_000];
    println!("n\tmethod\tlongest stall\tmedian\t(UI thread: key applied, frame drawn, 120x40)");
    let mut worst = Duration::ZERO;
    for &n in &sizes {
        for method in Method::ALL {
            let mut app = app(n, method);
            update(&mut app, Msg::Resize(120, 40));
            // The result of the state before is on screen, as after any earlier key.
            settle(&mut app);
            let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
            terminal.draw(|frame| view::draw(frame, &app)).unwrap();
            let mut stalls: Vec<Duration> = (0..KEYS)
                .map(|i| {
                    let start = Instant::now();
                    update(&mut app, key(i));
                    terminal.draw(|frame| view::draw(frame, &app)).unwrap();
                    start.elapsed()
                })
                .collect();
            stalls.sort();
            let longest = *stalls.last().unwrap();
            worst = worst.max(longest);
            println!(
                "{n}\t{method}\t{:.3} ms\t{:.3} ms",
                longest.as_secs_f64() * 1e3,
                stalls[KEYS / 2].as_secs_f64() * 1e3
            );
        }
    }
    println!(
        "longest stall over every n and method: {:.3} ms",
        worst.as_secs_f64() * 1e3
    );

    key_to_solution("benchmark-1");
    key_to_solution("benchmark-2");
    keys_at_many_obstacles(4000);
}

/// What one key costs the UI thread at `k` obstacles (n = 10⁴, condensed): the update alone,
/// and the update with the frame (a served session's flood of keys pays this per key).
fn keys_at_many_obstacles(k: usize) {
    let mut scene = Scene::from_toml(preset("benchmark-3").unwrap().text, "many").unwrap();
    scene.obstacles = (0..k)
        .map(|i| ObstacleSpec {
            x: (i + 1) as f64 / (k + 1) as f64,
            sliding: 20.0,
            swivel: 5.0,
        })
        .collect();
    scene.mesh.elements = 10_000;
    scene.solver.method = Method::Condensed;
    let loaded = LoadedScene::new(scene, SceneSource::Preset("benchmark-3")).unwrap();
    let look = Look {
        ascii: false,
        color: true,
    };
    let mut app = App::new(loaded, Options::new(look)).unwrap();
    update(&mut app, Msg::Resize(120, 40));
    let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
    let mut updates = Vec::new();
    let mut frames = Vec::new();
    for i in 0..200 {
        let start = Instant::now();
        update(&mut app, key(i));
        updates.push(start.elapsed());
        terminal.draw(|frame| view::draw(frame, &app)).unwrap();
        frames.push(start.elapsed());
    }
    updates.sort();
    frames.sort();
    println!(
        "a key at k = {k} obstacles, n = 10^4: update median {:.3} ms (longest {:.3} ms), with \
         the frame median {:.3} ms (longest {:.3} ms); undo keeps {} steps",
        updates[100].as_secs_f64() * 1e3,
        updates[199].as_secs_f64() * 1e3,
        frames[100].as_secs_f64() * 1e3,
        frames[199].as_secs_f64() * 1e3,
        app.history.undo_len()
    );
}

/// A key at n = 10⁶ (flexibility) on the preset `name` until the frame with its solution is
/// drawn; prints the median and the longest of 10 keys.
fn key_to_solution(name: &'static str) {
    let mut app = app_on(name, 1_000_000, Method::Flexibility);
    update(&mut app, Msg::Resize(120, 40));
    settle(&mut app);
    let mut terminal = Terminal::new(TestBackend::new(120, 40)).unwrap();
    let (sender, results) = channel();
    let mut worker: Worker<SolveRequest> =
        Worker::start("solver", 1, WorkerOptions::default(), move |result| {
            let _ = sender.send(result);
        });
    let mut times = Vec::new();
    for i in 0..10 {
        let start = Instant::now();
        update(&mut app, key(i));
        worker.want(0, app.exploration.pending_solve());
        terminal.draw(|frame| view::draw(frame, &app)).unwrap();
        let solved = results.recv().unwrap().unwrap();
        update(&mut app, Msg::Solved(Box::new(solved)));
        assert!(app.exploration.is_current());
        terminal.draw(|frame| view::draw(frame, &app)).unwrap();
        times.push(start.elapsed());
    }
    times.sort();
    println!(
        "key to solved frame, n = 10^6, flexibility, {name}: median {:.1} ms, longest {:.1} ms",
        times[5].as_secs_f64() * 1e3,
        times[9].as_secs_f64() * 1e3
    );
}

//! What `present --record` costs the recorder thread: the time to write a cast of 1 to 256 MB
//! whole beside its target and rename it over (what it does two seconds after a change), and
//! with fsync (what it does at the end). The UI thread only sends each frame's bytes over a
//! channel; this is the disk work behind it. `cargo bench --bench record`.

use std::io::Write;
use std::time::Instant;

use beamfric::tui::runtime::record::{Output, Recording};

fn main() {
    let frame = "\u{1b}[12;30H⠤⠤⠔⠊ error 8.5e-5 vs closed form ".repeat(40);
    for megabytes in [1usize, 16, 64, 256] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bench.cast");
        let recording = Recording::start(&path, (120, 40), "bench").unwrap();
        let mut output = Output::sink(Some(recording.tap()));
        let frames = megabytes * (1 << 20) / frame.len();
        let started = Instant::now();
        for _ in 0..frames {
            output.write_all(frame.as_bytes()).unwrap();
            output.flush().unwrap();
        }
        let sent = started.elapsed();
        let started = Instant::now();
        let summary = recording.finish().unwrap();
        let finished = started.elapsed();
        println!(
            "{megabytes:>4} MB of frames ({frames} flushes): UI side {:.1} ms ({:.2} µs a frame); \
             the last whole write with fsync {:.0} ms; cast {:.1} MB{}",
            sent.as_secs_f64() * 1e3,
            sent.as_secs_f64() * 1e6 / frames as f64,
            finished.as_secs_f64() * 1e3,
            summary.bytes as f64 / 1e6,
            if summary.truncated {
                " (cut at the limit)"
            } else {
                ""
            }
        );
    }
}

//! `beamfric present` on a pty of its own, as a lecturer starts it: an open server on a free
//! loopback port, its host key in the test's folder, and the join screen it opens on.

use std::net::SocketAddr;
use std::path::Path;

use super::pty::PtyProcess;
use super::serve_process::port_in;

/// `beamfric present --open --listen 127.0.0.1:0 --host-key DIR/host_key EXTRA…` on a pty of
/// `size` (columns, rows).
pub fn present(dir: &Path, extra: &[&str], size: (u16, u16)) -> PtyProcess {
    let host_key = dir.join("host_key");
    let mut args = vec![
        "present",
        "--open",
        "--listen",
        "127.0.0.1:0",
        "--host-key",
        host_key.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    PtyProcess::start(&args, &[], size)
}

/// Waits for the join screen the lecturer's explorer opens on, closes it with a key, and
/// returns what it showed and the address students connect to.
pub fn past_the_join_screen(lecturer: &mut PtyProcess) -> (String, SocketAddr) {
    lecturer.wait_for_screen("Students join the class with");
    let join = lecturer.screen();
    let port = port_in(&join);
    lecturer.type_bytes(b"x");
    lecturer.wait_for_screen("students connect with");
    let address = format!("127.0.0.1:{port}").parse().unwrap();
    (join, address)
}

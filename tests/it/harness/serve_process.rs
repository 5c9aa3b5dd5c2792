//! `beamfric serve` (or `present`) as a process of its own, its log read line by line: for
//! what only a separate process shows (its own memory, its log, its exit).

use crate::harness::wait::PATIENCE;

/// `beamfric serve` as a process, its stderr read line by line.
pub struct ServeProcess {
    child: std::process::Child,
    lines: std::sync::mpsc::Receiver<String>,
    /// The lines read so far.
    pub seen: Vec<String>,
}

impl ServeProcess {
    pub fn start(args: &[&str]) -> ServeProcess {
        ServeProcess::start_with(args, &[])
    }

    /// As [`ServeProcess::start`], with `env` set in the process's environment.
    pub fn start_with(args: &[&str], env: &[(&str, &str)]) -> ServeProcess {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_beamfric"))
            .args(args)
            .envs(env.iter().copied())
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let stderr = child.stderr.take().unwrap();
        let (sender, lines) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            use std::io::BufRead;
            for line in std::io::BufReader::new(stderr).lines() {
                let Ok(line) = line else { return };
                if sender.send(line).is_err() {
                    return;
                }
            }
        });
        ServeProcess {
            child,
            lines,
            seen: Vec::new(),
        }
    }

    /// Its process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// The first line containing `needle` (panics after [`PATIENCE`]).
    pub fn wait_for_line(&mut self, needle: &str) -> String {
        if let Some(line) = self.seen.iter().find(|l| l.contains(needle)) {
            return line.clone();
        }
        loop {
            let line = self
                .lines
                .recv_timeout(PATIENCE)
                .unwrap_or_else(|_| panic!("no line with {needle:?}; so far: {:?}", self.seen));
            self.seen.push(line.clone());
            if line.contains(needle) {
                return line;
            }
        }
    }
}

impl Drop for ServeProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The port in a line "… listening on 127.0.0.1:PORT …".
pub fn port_in(line: &str) -> u16 {
    let after = line.split("127.0.0.1:").nth(1).expect("an address");
    let digits: String = after.chars().take_while(char::is_ascii_digit).collect();
    digits.parse().expect("a port")
}

//! The CPU time of a thread of this process, from `/proc`: something to wait for ("the solve
//! has worked for 100 ms of CPU") that proves work is under way however busy the machine is.

use std::time::Duration;

/// The calling thread's id (the `tid` of `/proc/self/task/<tid>`).
pub fn this_thread() -> u32 {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").expect("/proc is mounted");
    stat.split_whitespace()
        .next()
        .and_then(|tid| tid.parse().ok())
        .expect("a thread id")
}

/// User and system time thread `tid` has used so far; `None` once it has ended.
pub fn thread_time(tid: u32) -> Option<Duration> {
    task_time("self", tid)
}

/// [`thread_time`] of a thread of another process (`pid`).
pub fn thread_time_in(pid: u32, tid: u32) -> Option<Duration> {
    task_time(&pid.to_string(), tid)
}

/// User and system time of task `tid` of the process `/proc/<process>`.
fn task_time(process: &str, tid: u32) -> Option<Duration> {
    let stat = std::fs::read_to_string(format!("/proc/{process}/task/{tid}/stat")).ok()?;
    // The command name, in parentheses, may hold spaces: count the fields after it. They
    // start with the state (field 3); utime and stime are fields 14 and 15, in clock ticks.
    let fields: Vec<&str> = stat[stat.rfind(')')? + 1..].split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    // SAFETY: sysconf only reads a configuration value.
    let per_second = unsafe { nix::libc::sysconf(nix::libc::_SC_CLK_TCK) };
    let per_second = u64::try_from(per_second).ok().filter(|&n| n > 0)?;
    Some(Duration::from_secs_f64(ticks as f64 / per_second as f64))
}

/// The ids of this process's threads named `name` now.
pub fn threads_named(name: &str) -> Vec<u32> {
    tasks_named("self", name)
}

/// [`threads_named`] of another process (`pid`).
pub fn threads_named_in(pid: u32, name: &str) -> Vec<u32> {
    tasks_named(&pid.to_string(), name)
}

/// The ids of the tasks of `/proc/<process>` named `name`.
fn tasks_named(process: &str, name: &str) -> Vec<u32> {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{process}/task")) else {
        return Vec::new();
    };
    tasks
        .filter_map(|task| {
            let task = task.ok()?;
            let comm = std::fs::read_to_string(task.path().join("comm")).ok()?;
            if comm.trim_end() != name {
                return None;
            }
            task.file_name().to_str()?.parse().ok()
        })
        .collect()
}

//! Independent jobs (the factorization's sweeps over independent stretches, the certificate's
//! check of interior nodes) on two threads when the work is large enough to pay for one. No
//! equation of its own: it only shares out work.

/// Below this many blocks the sweeps run on one thread (spawning costs more than it saves).
const PARALLEL_BLOCKS: usize = 100_000;

/// Runs `work` on every job, on two threads when there is enough work (balanced by size).
pub(crate) fn run_jobs<J: Send, R: Send>(
    jobs: Vec<J>,
    size: impl Fn(&J) -> usize,
    work: impl Fn(J) -> R + Sync,
) -> Vec<R> {
    let total: usize = jobs.iter().map(&size).sum();
    // Asking for the core count reads cgroup files: only for work worth a thread, and once.
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    if total < PARALLEL_BLOCKS
        || jobs.len() < 2
        || *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get())) < 2
    {
        return jobs.into_iter().map(work).collect();
    }
    // Greedy split into two groups of similar size, keeping each job's index.
    let mut groups: [Vec<(usize, J)>; 2] = [Vec::new(), Vec::new()];
    let mut loads = [0usize; 2];
    let mut indexed: Vec<(usize, J)> = jobs.into_iter().enumerate().collect();
    indexed.sort_by_key(|(_, j)| std::cmp::Reverse(size(j)));
    for (i, job) in indexed {
        let g = usize::from(loads[1] < loads[0]);
        loads[g] += size(&job);
        groups[g].push((i, job));
    }
    let [mine, theirs] = groups;
    let work = &work;
    let mut results: Vec<(usize, R)> = std::thread::scope(|scope| {
        let other = scope.spawn(move || {
            theirs
                .into_iter()
                .map(|(i, j)| (i, work(j)))
                .collect::<Vec<_>>()
        });
        let mut here: Vec<(usize, R)> = mine.into_iter().map(|(i, j)| (i, work(j))).collect();
        here.extend(other.join().expect("a worker thread does not panic"));
        here
    });
    results.sort_by_key(|(i, _)| *i);
    results.into_iter().map(|(_, r)| r).collect()
}

//! The C library's allocator, set once for the whole process: memory a solve frees is kept
//! for the next solve rather than handed back to the system. No equation of the paper; a
//! matter of speed (issue 26, docs/numerics.md, "Freed memory kept for the next solve").
//!
//! glibc's `malloc` gives the top of its heap back to the system once more than a threshold
//! of it is free, and serves blocks above another threshold with a mapping of their own,
//! unmapped when freed. It raises both thresholds by itself as large blocks are freed, but a
//! solve at 1000–4000 obstacles frees more than that after every solve: the next solve then
//! finds its vectors (the factors, the interior-point steps, the refinement) in fresh pages,
//! each zeroed by the kernel on first touch. Page faults were 7 % of a solve of the clustered
//! family at k = 1000 in a loop of solves.
//!
//! Both thresholds are set to [`KEPT_BYTES`]: a heap keeps at most that much free memory at
//! its top (glibc has up to eight heaps per core, one per thread in use at once), and blocks
//! up to that size come from the heap. Elsewhere (other C libraries) nothing is changed.

/// Free memory a heap keeps, and the largest block served from a heap: 16 MiB. Measured in a
/// loop of solves (`GLIBC_TUNABLES` thresholds, fastest of 61): 4 MiB already gave the whole
/// gain at k = 4000 (random family 19.4 → 18.1 ms), 1 MiB not (20.3 ms); 16 MiB leaves room
/// for larger scenes.
pub const KEPT_BYTES: usize = 16 << 20;

/// Sets the allocator's thresholds to [`KEPT_BYTES`] (glibc on Linux; elsewhere nothing).
/// For a program's start, before its threads: `cli::dispatch` for every command but `serve`
/// and `present`, and the benchmarks, which measure what the binary does. Not for a server:
/// eight students solving a 3500-obstacle scene at once left `beamfric serve` with 125 MB
/// resident after they hung up, against 75 MB with glibc's own thresholds.
pub fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        let bytes = KEPT_BYTES as libc::c_int;
        // SAFETY: mallopt only sets two of glibc's malloc parameters, under its own lock; it
        // reads and writes no memory of ours. A refusal (return 0) leaves glibc's defaults,
        // which are only slower.
        unsafe {
            libc::mallopt(libc::M_MMAP_THRESHOLD, bytes);
            libc::mallopt(libc::M_TRIM_THRESHOLD, bytes);
        }
    }
}

//! The C library's allocator, set once for the whole process: memory a solve frees is kept
//! for the next solve rather than handed back to the system; and a server's ended sessions'
//! memory handed back ([`give_back_freed_memory`]). No equation of the paper; a
//! matter of speed (issue 26, docs/many-obstacles/close-obstacles-and-near-ties.md, "Cheaper steps,
//! and a solve's freed memory kept for the next (stop 50)").
//!
//! glibc's `malloc` gives the top of its heap back to the system once more than a threshold
//! of it is free, and serves blocks above another threshold with a mapping of their own,
//! unmapped when freed. It raises both thresholds by itself as large blocks are freed, but a
//! solve at 1000–4000 obstacles frees more than that after every solve: the next solve then
//! finds its vectors (the factors, the interior-point steps, the refinement) in fresh pages,
//! each zeroed by the kernel on first touch. Page faults were 7 % of a solve of the clustered
//! family at k = 1000 in a loop of solves.
//!
//! The trim threshold is set to [`KEPT_BYTES`]: an arena keeps at most that much free memory
//! at its top (glibc makes up to eight arenas per core on 64-bit systems, one per thread
//! allocating at once). The mmap threshold is set to glibc's own largest, 32 MiB, so blocks up
//! to that size come from an arena. Setting either stops glibc from moving them by itself.
//! Elsewhere (other C libraries) nothing is changed.

/// Free memory an arena keeps: 16 MiB. Measured in a loop of solves (`GLIBC_TUNABLES`
/// thresholds, fastest of 61): 4 MiB already gave the whole gain at k = 4000 (random family
/// 19.4 → 18.1 ms), 1 MiB not (20.3 ms); 16 MiB leaves room for larger scenes.
pub const KEPT_BYTES: usize = 16 << 20;

/// The largest block served from an arena rather than mapped on its own: glibc's own upper
/// bound for the threshold it would raise by itself on 64-bit systems.
pub const LARGEST_FROM_ARENA: usize = 32 << 20;

/// Sets the allocator's trim threshold to [`KEPT_BYTES`] and its mmap threshold to
/// [`LARGEST_FROM_ARENA`] (glibc on Linux; elsewhere nothing). Called by the binary's `main`
/// for every command but `serve` and `present`, and by the `many_obstacles` benchmark, which
/// measures what the binary does. Not for a server: eight students solving a 3500-obstacle
/// scene at once left `beamfric serve` with 125 MB resident after they hung up, against
/// 75 MB with glibc's own thresholds.
///
/// # Safety
///
/// No other thread may be running: glibc's `mallopt` is not safe to call while other
/// threads allocate (it changes parameters they read without its lock). Call it first thing
/// in `main`.
pub unsafe fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: the caller guarantees no other thread runs; mallopt then only sets two of
        // glibc's parameters and touches no memory of ours. A refusal (return 0) leaves
        // glibc's own thresholds, which are only slower.
        unsafe {
            libc::mallopt(libc::M_MMAP_THRESHOLD, LARGEST_FROM_ARENA as libc::c_int);
            libc::mallopt(libc::M_TRIM_THRESHOLD, KEPT_BYTES as libc::c_int);
        }
    }
}

/// Hands the memory the allocator holds free back to the system (glibc's `malloc_trim`: free
/// pages in every arena, not only at the top of each heap; elsewhere nothing). Called by
/// `serve` when a session ends: glibc keeps an arena per thread that allocated at once, and
/// the pages a session's solves freed stayed resident. Twelve sessions at n = 10⁵ with keys
/// held down, closed and opened again round after round, took the server from 13 MB to
/// 367 MB after eleven rounds (stop 58's hostile pass); with this, the server stays at
/// 17–45 MB between rounds (`docs/classroom.md`, Memory).
pub fn give_back_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim takes each arena's lock and only releases pages no allocation
    // holds; it is safe to call from any thread at any time.
    unsafe {
        libc::malloc_trim(0);
    }
}

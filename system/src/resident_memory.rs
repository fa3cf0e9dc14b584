//! Resident memory that follows what a process holds, so that a soak's
//! memory growth is a leak signal and not the allocator's bookkeeping.
//!
//! glibc serves an allocation of 128 KiB or more with its own mapping, and
//! when such a block is freed it raises that threshold to the block's size
//! (`mallopt(3)`, "dynamic mmap threshold"): the next block of that size
//! comes from the heap, is zeroed there, and stays resident after it is
//! freed. A process that builds a large buffer now and then (the latency
//! histograms, about 256 KiB of counts and a 288 KiB encoding buffer, every
//! ten seconds) thus grows once, by a few hundred KiB, at the second
//! time it does so: a step a soak took for a leak when it fell after the
//! warm-up. Setting the threshold fixes it at glibc's default, so large
//! blocks are always mapped, and unmapped when freed.

/// Glibc's default mmap threshold, bytes.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MMAP_THRESHOLD: libc::c_int = 128 * 1024;

/// Makes freed large blocks go back to the system at once (see the module's
/// documentation); a process calls it first thing in `main`. Elsewhere than
/// glibc it does nothing.
pub fn return_large_blocks_when_freed() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets an allocator parameter; called before any
    // thread is started.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
    }
}

//! The program's allocator: jemalloc, with its options chosen for the
//! time of one frame within a bound on its peak memory, and a second
//! setting for animations, whose frames free and make the same amount of
//! memory again and again.

/// jemalloc: the tree and the records are hundreds of thousands of small
/// blocks made and freed by several threads, where glibc's allocator spent
/// 15-25 % of the cycles (consolidating its fast bins on every large free).
#[global_allocator]
static ALLOCATOR: tikv_jemallocator::Jemalloc = tikv_jemallocator::Jemalloc;

/// jemalloc's options (its `malloc_conf`; `_RJEM_MALLOC_CONF` in the
/// environment still overrides them), chosen for the time of a frame
/// within a peak of 64 MiB for office2 at 512x512:
/// - `dirty_decay_ms:100,muzzy_decay_ms:0`: pages freed for 100 ms go
///   back to the system. With the default 10 s, what the tree builder
///   frees stayed resident to the end: 72 MB peak, against 58 MB with
///   10 ms (when the tree was larger than it is now). 100 ms rather than
///   10 gives back less during a still and faults less in again:
///   office2 113.5 against 116.3 ms (7 ms less CPU), without shadows 28.2
///   against 29.5 ms, for a peak of 42-46 MB instead of 40.
/// - `thp:always`: transparent huge pages where the system allows them
///   (its `madvise` setting, or `always`). A still faults in far fewer
///   pages: office2 without shadows took 2 ms less (32.7 against 34.8 ms,
///   4 ms less CPU), office2 5 ms less and gallery 2.4 ms less. A huge
///   page is held wherever any of it is used: office2's peak is 40 MB
///   instead of 27, the ten-million-triangle mesh's 3.36 GB instead of
///   3.33. The smallest scenes (ccube) take 0.4 ms more.
///
/// Not `percpu_arena:percpu` (one arena per CPU, 57 MB instead of 60): when
/// the process may run on fewer CPUs than the machine has (`taskset`, a
/// Slurm or Kubernetes cpuset), jemalloc then prints a warning on every
/// run.
#[unsafe(export_name = "_rjem_malloc_conf")]
static MALLOC_CONF: MallocConf =
    MallocConf(c"thp:always,dirty_decay_ms:100,muzzy_decay_ms:0".as_ptr());

/// A C string pointer jemalloc reads once at start-up.
#[repr(transparent)]
struct MallocConf(*const std::ffi::c_char);

// SAFETY: the pointer is to a string literal, never written.
unsafe impl Sync for MallocConf {}

/// How long pages freed in an animation stay resident (ms): each frame
/// then reuses the pages the last one freed instead of giving them back
/// and faulting them in again. On a 120-frame walk through office2 this
/// cut the time from 10.5 s to 8.9 s, for a peak of 77 MB instead of 60.
const ANIMATION_DECAY_MS: isize = 5000;

/// From the second `run` of a session on, freed pages stay resident for
/// [`ANIMATION_DECAY_MS`]; the first frame keeps the low peak of a still.
/// If jemalloc refuses, the setting stays as it was (it only costs time).
pub fn keep_freed_pages() {
    let arenas = read_u32(c"arenas.narenas").unwrap_or(0);
    for i in 0..arenas {
        if let Ok(name) = std::ffi::CString::new(format!("arena.{i}.dirty_decay_ms")) {
            write_isize(&name, ANIMATION_DECAY_MS);
        }
    }
    // The default of arenas made later.
    write_isize(c"arenas.dirty_decay_ms", ANIMATION_DECAY_MS);
}

/// Reads jemalloc's unsigned option `name`.
fn read_u32(name: &std::ffi::CStr) -> Option<u32> {
    let mut value: u32 = 0;
    let mut len = std::mem::size_of::<u32>();
    // SAFETY: a NUL-terminated name, and a u32 with its size, as
    // jemalloc's `unsigned` options are read; nothing is written.
    let rc = unsafe {
        tikv_jemalloc_sys::mallctl(
            name.as_ptr(),
            (&raw mut value).cast(),
            &raw mut len,
            std::ptr::null_mut(),
            0,
        )
    };
    (rc == 0).then_some(value)
}

/// Sets jemalloc's `ssize_t` option `name` to `value`; a refusal (an
/// arena not yet made) leaves it as it was.
fn write_isize(name: &std::ffi::CStr, mut value: isize) {
    // SAFETY: a NUL-terminated name and a pointer to an isize of the size
    // given, as jemalloc's ssize_t options take; nothing is read.
    unsafe {
        tikv_jemalloc_sys::mallctl(
            name.as_ptr(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            (&raw mut value).cast(),
            std::mem::size_of::<isize>(),
        );
    }
}

//! `--threads N`: the one place a render's pool of threads is made, with
//! one policy. `0` is every core (rayon's global pool); `N` is a pool of
//! its own, and a system that cannot start its threads is an error, not a
//! silent fall back to another number. One thread gives the same image as
//! many: the threads only share out work whose results are put back in
//! order.

use crate::error::{Error, Result};

/// The most threads a pool may have: each is a stack and a system
/// thread, made when the pool starts; more than this is refused before
/// any is made.
pub const MAX_THREADS: usize = 1024;

/// The threads a render's parallel work runs on.
pub struct Pool(Option<rayon::ThreadPool>);

impl Pool {
    /// `threads` threads, or every core for `0`.
    pub fn new(threads: usize) -> Result<Pool> {
        if threads == 0 {
            return Ok(Pool(None));
        }
        if threads > MAX_THREADS {
            return Err(Error::Invalid(format!(
                "cannot start {threads} threads: a render uses at most {MAX_THREADS}"
            )));
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map(|p| Pool(Some(p)))
            .map_err(|e| Error::Invalid(format!("cannot start {threads} threads: {e}")))
    }

    /// Runs `f` on a thread of the pool, so that its many parallel steps
    /// start from inside it. Called from outside, each step's `join`
    /// would be handed to the pool and this thread would wait for it (the
    /// tree of office2 without shadows took longer on two threads than on
    /// one that way).
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match &self.0 {
            Some(pool) => pool.install(f),
            None => rayon::scope(|_| f()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn n_threads_are_n_and_zero_is_every_core() {
        let two = Pool::new(2).unwrap();
        assert_eq!(two.install(rayon::current_num_threads), 2);
        let all = Pool::new(0).unwrap();
        assert_eq!(
            all.install(rayon::current_num_threads),
            rayon::current_num_threads()
        );
    }

    #[test]
    fn too_many_threads_are_refused_before_any_is_made() {
        let e = Pool::new(MAX_THREADS + 1).err().expect("refused");
        assert!(e.to_string().contains("at most 1024"), "{e}");
        assert!(Pool::new(MAX_THREADS).is_ok());
    }
}

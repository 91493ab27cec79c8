//! The simulation's own worker pool. Dropping it waits until every worker thread has exited,
//! so that a host can unload the library (a Unity or Unreal plugin) right after destroying a
//! simulation, and leak checkers see no thread left running.

use crate::error::{Error, Result};
use rayon::prelude::*;
use std::sync::{Arc, Condvar, Mutex};

/// A rayon pool whose drop joins its threads.
#[derive(Debug)]
pub struct Pool {
    pool: Option<rayon::ThreadPool>,
    alive: Arc<(Mutex<usize>, Condvar)>,
}

impl Pool {
    /// Starts `threads` workers named `wethair-N`.
    pub fn new(threads: usize) -> Result<Pool> {
        let alive = Arc::new((Mutex::new(threads), Condvar::new()));
        let on_exit = alive.clone();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("wethair-{i}"))
            .start_handler(|_| super::denormals::FlushDenormals::forever())
            .exit_handler(move |_| {
                let (count, cv) = &*on_exit;
                let mut n = count.lock().unwrap_or_else(|e| e.into_inner());
                *n -= 1;
                cv.notify_all();
            })
            .build()
            .map_err(|e| Error::Capacity(format!("could not start {threads} threads: {e}")))?;
        Ok(Pool {
            pool: Some(pool),
            alive,
        })
    }

    /// Worker threads.
    pub fn threads(&self) -> usize {
        self.pool.as_ref().expect("pool lives until drop").current_num_threads()
    }

    /// Runs `f` on the pool (the caller waits).
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        self.pool.as_ref().expect("pool lives until drop").install(f)
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        drop(self.pool.take());
        let (count, cv) = &*self.alive;
        let mut n = count.lock().unwrap_or_else(|e| e.into_inner());
        while *n > 0 {
            n = cv.wait(n).unwrap_or_else(|e| e.into_inner());
        }
    }
}

/// Runs `f(first, chunk)` over `items` in chunks of `size`, on the pool when there is one.
/// Each chunk is written by one task, so the result does not depend on the thread count.
pub fn for_chunks<T: Send>(pool: Option<&Pool>, items: &mut [T], size: usize, f: impl Fn(usize, &mut [T]) + Sync) {
    match pool {
        Some(pool) => pool.install(|| {
            items
                .par_chunks_mut(size)
                .enumerate()
                .for_each(|(c, out)| f(c * size, out))
        }),
        None => f(0, items),
    }
}

/// [`for_chunks`] over two slices of equal length at once: `f(first, a_chunk, b_chunk)`.
pub fn for_chunks2<T: Send, U: Send>(
    pool: Option<&Pool>,
    a: &mut [T],
    b: &mut [U],
    size: usize,
    f: impl Fn(usize, &mut [T], &mut [U]) + Sync,
) {
    debug_assert_eq!(a.len(), b.len());
    match pool {
        Some(pool) => pool.install(|| {
            a.par_chunks_mut(size)
                .zip(b.par_chunks_mut(size))
                .enumerate()
                .for_each(|(c, (x, y))| f(c * size, x, y))
        }),
        None => f(0, a, b),
    }
}

/// `v` in chunks of `size`, or `n` empty slices when `v` is empty (a per-row buffer the scene
/// does not have).
pub fn chunks_or_empty<T: Send>(v: &mut [T], size: usize, n: usize) -> impl IndexedParallelIterator<Item = &mut [T]> {
    if v.is_empty() {
        rayon::iter::Either::Right((0..n).into_par_iter().map(|_| <&mut [T]>::default()))
    } else {
        rayon::iter::Either::Left(v.par_chunks_mut(size))
    }
}

//! A level's chunks prepared on every thread and added to the tree in
//! order (Garcia 1986, 004 section 4.7: the shadows of a level's
//! fragments do not depend on the tree, so they are found ahead of it).
//!
//! Each chunk is a list of tasks: one for the whole chunk, then one per
//! item in an order the job chooses. The threads take tasks in that order
//! across at most [`Job::AHEAD`] chunks, and the calling thread adds each
//! chunk as soon as it and those before it are done, taking tasks itself
//! while it waits. No thread waits at the end of a chunk while another
//! finishes its longest task, as a chunk-at-a-time barrier did; and the
//! chunks held at once stay bounded.
//!
//! The tasks never wait on each other, so a task that runs parallel work
//! of its own (or a thread that takes up a task while it waits inside
//! such work) cannot block the pipeline; only the calling thread waits,
//! and only for tasks that running threads have taken.

use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};

/// What a pipeline does with each chunk.
pub(super) trait Job: Sync {
    /// A chunk of items.
    type Chunk: Send + Sync;
    /// What the chunk's first task makes for the whole chunk.
    type Whole: Send;
    /// What an item's task makes.
    type Item: Send;
    /// Chunks prepared at once, beside the one being added (at least 1).
    const AHEAD: usize;
    /// How many items the chunk has.
    fn items(&self, chunk: &Self::Chunk) -> usize;
    /// The positions of the chunk's items to make, in the order to take
    /// them; the others get none.
    fn order(&self, chunk: &Self::Chunk) -> Vec<u32>;
    /// The whole chunk's task.
    fn whole(&self, chunk: &Self::Chunk) -> Self::Whole;
    /// The task of the item at position `i`.
    fn item(&self, chunk: &Self::Chunk, i: u32) -> Self::Item;
}

/// A chunk being prepared.
struct Open<J: Job> {
    chunk: Arc<J::Chunk>,
    order: Vec<u32>,
    whole: Option<J::Whole>,
    /// By position in the chunk.
    items: Vec<Option<J::Item>>,
    /// Tasks handed out: the whole chunk's first, then `order`'s.
    taken: usize,
    /// Tasks not yet done.
    left: usize,
}

impl<J: Job> Open<J> {
    fn new(job: &J, chunk: J::Chunk) -> Open<J> {
        let (order, len) = (job.order(&chunk), job.items(&chunk));
        let left = order.len() + 1;
        Open {
            chunk: Arc::new(chunk),
            order,
            whole: None,
            items: std::iter::repeat_with(|| None).take(len).collect(),
            taken: 0,
            left,
        }
    }
}

/// A task taken from chunk number `seq`.
struct Task<C> {
    seq: usize,
    chunk: Arc<C>,
    /// The item's position, for an item's task.
    item: Option<u32>,
}

/// What a task made.
enum Made<J: Job> {
    Whole(J::Whole),
    Item(u32, J::Item),
}

struct State<J: Job> {
    open: VecDeque<Open<J>>,
    /// The number of `open`'s first chunk.
    first: usize,
    /// Worker loops running.
    workers: usize,
    /// A task panicked: the calling thread stops waiting.
    failed: bool,
}

impl<J: Job> State<J> {
    fn take(&mut self) -> Option<Task<J::Chunk>> {
        let (k, open) = self
            .open
            .iter_mut()
            .enumerate()
            .find(|(_, o)| o.taken <= o.order.len())?;
        let task = open.taken;
        open.taken += 1;
        Some(Task {
            seq: self.first + k,
            chunk: Arc::clone(&open.chunk),
            item: task.checked_sub(1).map(|i| open.order[i]),
        })
    }

    /// Stores what a task of chunk `seq` made; whether that finished the
    /// first chunk (what the calling thread waits for).
    fn store(&mut self, seq: usize, made: Made<J>) -> bool {
        let open = &mut self.open[seq - self.first];
        match made {
            Made::Whole(w) => open.whole = Some(w),
            Made::Item(i, r) => open.items[i as usize] = Some(r),
        }
        open.left -= 1;
        seq == self.first && open.left == 0
    }

    /// The first chunk, with what was made for it, when it is done.
    fn done(&mut self) -> Option<Open<J>> {
        if self.open.front()?.left > 0 {
            return None;
        }
        self.first += 1;
        self.open.pop_front()
    }
}

struct Shared<J: Job> {
    state: Mutex<State<J>>,
    changed: Condvar,
}

impl<J: Job> Shared<J> {
    fn lock(&self) -> MutexGuard<'_, State<J>> {
        // A task panics outside the lock: the state is never half-changed.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Runs `task` (outside the lock) and stores what it made.
    fn run(&self, job: &J, task: Task<J::Chunk>) {
        let made = match task.item {
            None => Made::Whole(job.whole(&task.chunk)),
            Some(i) => Made::Item(i, job.item(&task.chunk, i)),
        };
        let seq = task.seq;
        // The chunk is let go first, so that once its last task is
        // stored the calling thread holds it alone.
        drop(task);
        // Only the calling thread waits, and only for the first chunk.
        if self.lock().store(seq, made) {
            self.changed.notify_one();
        }
    }

    /// A worker: tasks until none is left to take.
    fn work(&self, job: &J) {
        let _failed = OnPanic(self);
        loop {
            let task = {
                let mut st = self.lock();
                let task = st.take();
                if task.is_none() {
                    st.workers -= 1;
                }
                task
            };
            match task {
                Some(task) => self.run(job, task),
                None => return,
            }
        }
    }
}

/// Tells the calling thread, if a worker's task panics, to stop waiting.
struct OnPanic<'a, J: Job>(&'a Shared<J>);

impl<J: Job> Drop for OnPanic<'_, J> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.lock().failed = true;
            self.0.changed.notify_one();
        }
    }
}

/// Prepares `chunks` by `job` on every thread of
/// the pool and hands each, with what was made for it, to `add` on this
/// thread, in order. Item positions left out of the job's order get
/// `None`.
pub(super) fn in_order<J: Job>(
    job: &J,
    chunks: impl IntoIterator<Item = J::Chunk>,
    mut add: impl FnMut(J::Chunk, J::Whole, Vec<Option<J::Item>>),
) {
    let mut chunks = chunks.into_iter();
    let shared = Shared {
        state: Mutex::new(State {
            open: VecDeque::new(),
            first: 0,
            workers: 0,
            failed: false,
        }),
        changed: Condvar::new(),
    };
    let threads = rayon::current_num_threads();
    rayon::in_place_scope(|scope| {
        // Opens chunks up to the bound and starts workers for them.
        let fill = |held: usize, chunks: &mut dyn Iterator<Item = J::Chunk>| {
            let mut opened = Vec::new();
            for chunk in chunks.take(J::AHEAD.max(1).saturating_sub(held)) {
                opened.push(Open::new(job, chunk));
            }
            let mut st = shared.lock();
            st.open.extend(opened);
            let mut start = 0;
            while st.workers + 1 < threads {
                st.workers += 1;
                start += 1;
            }
            drop(st);
            for _ in 0..start {
                let shared = &shared;
                scope.spawn(move |_| shared.work(job));
            }
        };
        fill(0, &mut chunks);
        let mut st = shared.lock();
        loop {
            if st.failed {
                return;
            }
            if let Some(done) = st.done() {
                let held = st.open.len();
                drop(st);
                fill(held, &mut chunks);
                let chunk = Arc::into_inner(done.chunk).expect("every task let its chunk go");
                let whole = done.whole.expect("the whole chunk's task is done");
                add(chunk, whole, done.items);
            } else if let Some(task) = st.take() {
                drop(st);
                shared.run(job, task);
            } else if st.open.is_empty() {
                return;
            } else {
                st = shared.changed.wait(st).unwrap_or_else(|e| e.into_inner());
                continue;
            }
            st = shared.lock();
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Squares items, the odd ones only; the whole task sums the chunk.
    /// Some tasks take longer, so that threads finish out of order.
    struct Squares {
        running: AtomicUsize,
        most: AtomicUsize,
    }

    impl Job for Squares {
        type Chunk = Vec<u64>;
        type Whole = u64;
        type Item = u64;
        const AHEAD: usize = 2;
        fn items(&self, chunk: &Vec<u64>) -> usize {
            chunk.len()
        }
        fn order(&self, chunk: &Vec<u64>) -> Vec<u32> {
            // Largest first, the odd ones only.
            let mut order: Vec<u32> = (0..chunk.len() as u32)
                .filter(|&i| chunk[i as usize] % 2 == 1)
                .collect();
            order.sort_by_key(|&i| std::cmp::Reverse(chunk[i as usize]));
            order
        }
        fn whole(&self, chunk: &Vec<u64>) -> u64 {
            chunk.iter().sum()
        }
        fn item(&self, chunk: &Vec<u64>, i: u32) -> u64 {
            let now = self.running.fetch_add(1, Ordering::SeqCst) + 1;
            self.most.fetch_max(now, Ordering::SeqCst);
            let x = chunk[i as usize];
            if x.is_multiple_of(7) {
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
            self.running.fetch_sub(1, Ordering::SeqCst);
            x * x
        }
    }

    /// Each chunk back, with its sum and its odd items' squares.
    type Out = Vec<(Vec<u64>, u64, Vec<Option<u64>>)>;

    fn run(threads: usize, chunks: Vec<Vec<u64>>) -> (Out, usize) {
        let job = Squares {
            running: AtomicUsize::new(0),
            most: AtomicUsize::new(0),
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut out = Vec::new();
        pool.install(|| in_order(&job, chunks, |c, w, i| out.push((c, w, i))));
        (out, job.most.load(Ordering::SeqCst))
    }

    /// Every chunk comes back once, in order, with each of its tasks'
    /// results in place, whatever the threads; the threads did overlap.
    #[test]
    fn chunks_come_back_in_order_whatever_the_threads() {
        let chunks: Vec<Vec<u64>> = (0..40u64)
            .map(|c| (0..(c % 9)).map(|i| c * 10 + i).collect())
            .collect();
        let expected: Out = chunks
            .iter()
            .map(|c| {
                let items = c.iter().map(|&x| (x % 2 == 1).then_some(x * x)).collect();
                (c.clone(), c.iter().sum(), items)
            })
            .collect();
        let (one, most) = run(1, chunks.clone());
        assert_eq!(one, expected);
        assert_eq!(most, 1);
        let (four, most) = run(4, chunks);
        assert_eq!(four, expected);
        assert!(most > 1, "the threads never overlapped");
    }

    /// No chunks, and chunks without items, come back as they are.
    #[test]
    fn empty_chunks_pass_through() {
        assert!(run(3, Vec::new()).0.is_empty());
        let (out, _) = run(3, vec![Vec::new(), vec![2, 4]]);
        assert_eq!(
            out,
            vec![
                (Vec::new(), 0, Vec::new()),
                (vec![2, 4], 6, vec![None, None])
            ]
        );
    }

    /// A task that panics makes the pipeline panic, not hang.
    #[test]
    fn a_panicking_task_is_not_a_hang() {
        struct Fails;
        impl Job for Fails {
            type Chunk = Vec<u64>;
            type Whole = ();
            type Item = ();
            const AHEAD: usize = 1;
            fn items(&self, chunk: &Vec<u64>) -> usize {
                chunk.len()
            }
            fn order(&self, chunk: &Vec<u64>) -> Vec<u32> {
                (0..chunk.len() as u32).collect()
            }
            fn whole(&self, _: &Vec<u64>) {}
            fn item(&self, chunk: &Vec<u64>, i: u32) {
                assert!(chunk[i as usize] != 13, "thirteen");
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let chunks: Vec<Vec<u64>> = (0..10u64).map(|c| vec![c, c + 10]).collect();
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            pool.install(|| in_order(&Fails, chunks, |_, (), _| {}))
        }));
        assert!(r.is_err());
    }
}

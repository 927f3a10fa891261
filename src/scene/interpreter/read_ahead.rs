//! Object files read ahead of their `endobj`, on other threads. A scene
//! file is checked whole before its first statement runs (004 appendix B
//! reads a descriptor file through), so its `defobj` blocks are known at
//! once; reading and parsing their geometry files is most of the time
//! spent reading a furnished scene, and the files do not depend on one
//! another. They are read in the order they appear, while the
//! interpreter runs the statements before them.
//!
//! What the interpreter takes is exactly what it would have read itself:
//! a read ahead is used only by a statement reading the same path, and
//! only when it succeeded within the budget that statement allows; every
//! other case (an error, a file that does not fit, a read not started
//! yet) is read again in turn, so the error is the same. A file that
//! several statements of one scene file read (office2 reads `cube.det`
//! 139 times) is read once, and its objects share the mesh. The notes the
//! reading makes (the files an output may not overwrite, the hashes of
//! the inputs' contents) are entered when the interpreter takes the
//! mesh, so they stay in statement order. Reading ahead is bounded: files
//! of at most [`MAX_FILE_BYTES`], at most [`MAX_TOTAL_BYTES`],
//! [`MAX_READS`] files and [`MAX_STATEMENTS`] statements in one run of a
//! scene, and what a run leaves unread is dropped at its end.

use std::collections::{HashMap, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};

use super::Interpreter;
use super::objects::read_geometry;
use crate::input_guard::{self, Notes};
use crate::model::Mesh;
use crate::scene::command::{Command, Parsed};

/// The largest object file read ahead.
pub const MAX_FILE_BYTES: u64 = 8 << 20;

/// The most bytes of object files read ahead in one run of a scene.
pub const MAX_TOTAL_BYTES: u64 = 64 << 20;

/// The most files read ahead in one run of a scene.
pub const MAX_READS: usize = 4096;

/// The most statements given a read ahead in one run of a scene (a scene
/// file of sixteen million bytes may hold two million `getobj`s); each
/// holds its path until it runs.
pub const MAX_STATEMENTS: usize = 1 << 16;

impl Interpreter {
    /// Starts reading the object files that `commands`, a file of folder
    /// `dir` just parsed, will read at their `endobj` (or `getobj`):
    /// every definition that neither copies nor generates its object,
    /// looked up as the interpreter will, following the file's own
    /// `det_dir`s. A guess that turns out wrong costs a read, not a
    /// result: the interpreter takes only a read of the path it looks up.
    pub(super) fn start_reading_ahead(&mut self, commands: &[Parsed], dir: &Path) {
        let (det_dir, det_base) = (self.det_dir.clone(), self.det_base.clone());
        let mut paths = Vec::new();
        // Each name is looked up once for the same folders in a run
        // (`object_file`), found or not.
        for (k, parsed) in commands.iter().enumerate() {
            if paths.len() >= MAX_STATEMENTS - self.read_ahead.statements {
                break;
            }
            let name = match &parsed.command {
                Command::DetDir(d) => {
                    self.det_dir = PathBuf::from(d);
                    self.det_base = dir.to_path_buf();
                    continue;
                }
                Command::Getobj(name) => name,
                Command::Defobj { name, .. } if reads_file(&commands[k + 1..]) => name,
                _ => continue,
            };
            paths.extend(self.object_file(name, dir));
        }
        (self.det_dir, self.det_base) = (det_dir, det_base);
        let budget = self.budgets.polygons;
        self.read_ahead.start(paths, budget, read_geometry);
    }
}

/// Whether the definition whose body starts `body` reads its object file:
/// no command before its `endobj` copies or generates the object.
fn reads_file(body: &[Parsed]) -> bool {
    use Command as C;
    body.iter()
        .map(|parsed| &parsed.command)
        .find(|c| matches!(c, C::Endobj | C::Defobj { .. } | C::Getobj(_)) || c.makes_object())
        .is_none_or(|c| !c.makes_object())
}

/// The reading of one object file, for the statements of one scene file
/// that read its path.
#[derive(Debug)]
struct Slot {
    path: PathBuf,
    max_polygons: usize,
    read: Reader,
    state: Mutex<State>,
    done: Condvar,
}

/// How far a slot's reading is.
#[derive(Debug)]
enum State {
    /// Not started.
    Queued,
    /// Being read.
    Reading,
    /// Read; `None` if it failed or was not read. Each statement takes
    /// a copy of the mesh's handle and of the notes.
    Read(Option<(Arc<Mesh>, Notes)>),
}

/// The reads still queued, shared with the threads reading them.
#[derive(Debug, Default)]
struct Queue {
    slots: Mutex<VecDeque<Arc<Slot>>>,
    /// Bytes read ahead so far.
    bytes: AtomicU64,
}

/// The object files read ahead for one interpreter, by path, in the
/// order their statements come.
#[derive(Debug, Clone, Default)]
pub struct ReadAhead {
    by_path: HashMap<PathBuf, VecDeque<Arc<Slot>>>,
    queue: Arc<Queue>,
    /// Files queued in this run.
    reads: usize,
    /// Statements given a read in this run.
    statements: usize,
}

impl ReadAhead {
    /// Starts reading `paths` (object files, in statement order) with at
    /// most `max_polygons` polygons each, by `read`.
    pub fn start(&mut self, paths: Vec<PathBuf>, max_polygons: usize, read: Reader) {
        let reads = self.enqueue(paths, max_polygons, read);
        // One thread fewer than the pool has: the interpreter, which
        // builds each object as its statement comes, is the third thread
        // on two cores otherwise, and waits its turn for a core.
        let workers = (rayon::current_num_threads() - 1).max(1).min(reads);
        for _ in 0..workers {
            let queue = self.queue.clone();
            rayon::spawn(move || queue.run());
        }
    }

    /// Queues the reads of `paths` for the statements that will take
    /// them, one a path (within the run's bounds: a statement past them
    /// reads its file itself); returns how many reads are now queued.
    fn enqueue(&mut self, mut paths: Vec<PathBuf>, max_polygons: usize, read: Reader) -> usize {
        paths.truncate(MAX_STATEMENTS - self.statements);
        let mut queued = self.queue.slots.lock().unwrap_or_else(|e| e.into_inner());
        // One read a path: each statement reading it is given the slot.
        let mut slots: HashMap<PathBuf, Arc<Slot>> = HashMap::new();
        for path in paths {
            let slot = match slots.get(&path) {
                Some(slot) => slot.clone(),
                None if self.reads < MAX_READS => {
                    let slot = Arc::new(Slot {
                        path: path.clone(),
                        max_polygons,
                        read,
                        state: Mutex::new(State::Queued),
                        done: Condvar::new(),
                    });
                    self.reads += 1;
                    queued.push_back(slot.clone());
                    slots.insert(path.clone(), slot.clone());
                    slot
                }
                None => continue,
            };
            self.statements += 1;
            self.by_path.entry(path).or_default().push_back(slot);
        }
        queued.len()
    }

    /// The mesh read ahead for the next statement reading `path`, with
    /// the notes its reading made, if it was read without error; else
    /// `None`, and the caller reads the file itself. Waits for a read
    /// under way; one not started is read now, on this thread, as a
    /// reading thread would (the statements after that share its path
    /// share the read).
    pub fn take(&mut self, path: &Path) -> Option<(Arc<Mesh>, Notes)> {
        let slots = self.by_path.get_mut(path)?;
        let slot = slots.pop_front()?;
        if slots.is_empty() {
            self.by_path.remove(path);
        }
        if slot.claim() {
            slot.fill(&self.queue);
        }
        // While another thread reads it, this one reads the files queued
        // after it rather than wait: a scene of many files is read by
        // every thread the pool has, not one.
        while !slot.is_read() && self.queue.read_next() {}
        let mut state = slot.state.lock().unwrap_or_else(|e| e.into_inner());
        while matches!(*state, State::Reading) {
            state = slot.done.wait(state).unwrap_or_else(|e| e.into_inner());
        }
        match &*state {
            State::Read(read) => read.clone(),
            State::Queued | State::Reading => unreachable!("claimed and waited for"),
        }
    }

    /// Gives up every read not started and drops the reads not taken;
    /// reads under way finish unused. The next run may read ahead
    /// [`MAX_TOTAL_BYTES`], [`MAX_READS`] and [`MAX_STATEMENTS`] again.
    pub fn clear(&mut self) {
        self.queue
            .slots
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        self.by_path.clear();
        self.queue.bytes.store(0, Ordering::Relaxed);
        self.reads = 0;
        self.statements = 0;
    }
}

/// How a file is read: its path and polygon budget to its mesh.
pub type Reader = fn(&Path, usize) -> crate::error::Result<Mesh>;

impl Slot {
    /// Whether the caller is the one to read the file: it was not
    /// started, and is now being read.
    fn claim(&self) -> bool {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let queued = matches!(*state, State::Queued);
        if queued {
            *state = State::Reading;
        }
        queued
    }

    /// Whether the file's reading is over.
    fn is_read(&self) -> bool {
        let state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        matches!(*state, State::Read(_))
    }

    /// Reads the claimed file and wakes the statements waiting for it.
    fn fill(&self, queue: &Queue) {
        let result = queue.read(self);
        *self.state.lock().unwrap_or_else(|e| e.into_inner()) = State::Read(result);
        self.done.notify_all();
    }
}

impl Queue {
    /// Reads queued files, in order, until none is left.
    fn run(&self) {
        while self.read_next() {}
    }

    /// Reads the next queued file, unless another thread has claimed it;
    /// `false` when none is queued.
    fn read_next(&self) -> bool {
        let next = self
            .slots
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .pop_front();
        let Some(slot) = next else {
            return false;
        };
        if slot.claim() {
            slot.fill(self);
        }
        true
    }

    /// One file read, within the bounds, with its notes held back.
    fn read(&self, slot: &Slot) -> Option<(Arc<Mesh>, Notes)> {
        let read = slot.read;
        let size = std::fs::metadata(&slot.path).ok()?.len();
        if size > MAX_FILE_BYTES
            || self.bytes.fetch_add(size, Ordering::Relaxed) + size > MAX_TOTAL_BYTES
        {
            return None;
        }
        // A panic is left to the interpreter's own reading of the file.
        let run = || input_guard::recording(|| read(&slot.path, slot.max_polygons));
        let (mesh, notes) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(run)).ok()?;
        mesh.ok().map(|mesh| (Arc::new(mesh), notes))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input_guard::{content_hash, contents};
    use crate::scene::NoHost;

    /// Writes `text` at `dir/name`, returning the path and its contents'
    /// hash.
    fn write(dir: &Path, name: &str, text: &str) -> (PathBuf, u64) {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
        (path, content_hash(text.as_bytes()))
    }

    /// An ASCII object file of one polygon of `n` points, its first
    /// point at `x` (so that no other test reads the same contents).
    fn polygon(n: usize, x: f64) -> String {
        let mut text = format!("data\n{n} 1\n");
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            text += &format!("{} {} 0\n", x + a.cos(), -a.sin());
        }
        text += &format!("{n}");
        for k in 1..=n {
            text += &format!(" {k}");
        }
        text + "\n"
    }

    #[test]
    fn each_statement_reads_its_own_file_and_notes_it_in_its_turn() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let x = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .subsec_nanos() as f64;
        let (ax, ax_h) = write(d, "a/x.det", &polygon(3, x));
        let (ay, ay_h) = write(d, "a/y.det", &polygon(4, x));
        let (bx, bx_h) = write(d, "b/x.det", &polygon(5, x));
        let (_, other_h) = write(d, "other.des", &format!("defobj y\nendobj\n# {x}\n"));
        // `defobj y` with `sphere` generates its object: `a/y.det` is
        // not read there.
        let scene_text = format!(
            "ident\ndet_dir a\ndefobj x\nendobj\ncall other.des\ndet_dir b\ndefobj x\nendobj\n\
             det_dir a\ndefobj y\nsphere 6 4\nendobj\ngetobj y\n# {x}\n"
        );
        let (scene, scene_h) = write(d, "scene.des", &scene_text);
        let mut interp = Interpreter::new();
        interp.execute_file(&scene, true, &mut NoHost).unwrap();
        // In the order the statements read them, whatever the threads.
        let ours = [scene_h, ax_h, other_h, ay_h, bx_h, ay_h];
        let noted: Vec<u64> = contents()
            .into_iter()
            .filter(|h| ours.contains(h))
            .collect();
        assert_eq!(noted, ours);
        // An output may not overwrite a file read ahead.
        assert!(input_guard::check(&bx).is_err());
        let objects = &interp.current().objects;
        let read = |p: &Path| crate::scene::object_file::read_det(p).unwrap();
        let expected = [Some(&ax), Some(&ay), Some(&bx), None, Some(&ay)];
        assert_eq!(objects.len(), expected.len());
        for (k, (o, path)) in objects.iter().zip(expected).enumerate() {
            match path {
                Some(path) => assert_eq!(*o.mesh, read(path), "object {k}"),
                None => assert_eq!(o.mesh.polygons.len(), 6 * 4, "the sphere"),
            }
        }
    }

    impl ReadAhead {
        /// Waits until every queued read is done.
        fn settle(&self) {
            let busy =
                |s: &Arc<Slot>| matches!(*s.state.lock().unwrap(), State::Queued | State::Reading);
            while self.by_path.values().flatten().any(busy) {
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
        }
    }

    /// A run looks each object file up once, and the next run finds the
    /// files as they are then: a `.det` file written between two runs
    /// comes before the `.obj` mesh of the same name the first run found.
    #[test]
    fn each_run_finds_the_object_files_as_they_are_then() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        write(d, "det/x.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let (scene, _) = write(d, "s.des", "ident\ngetobj x\ngetobj x\n");
        let points = |interp: &mut Interpreter| -> Vec<usize> {
            let objects = &interp.current().objects;
            objects
                .iter()
                .map(|o| o.polygons[0].indices.len())
                .collect()
        };
        let mut interp = Interpreter::new();
        interp.execute_file(&scene, true, &mut NoHost).unwrap();
        assert_eq!(points(&mut interp), [3, 3]);
        write(d, "det/x.det", &polygon(4, 0.25));
        interp.execute_file(&scene, true, &mut NoHost).unwrap();
        assert_eq!(points(&mut interp), [4, 4]);
    }

    #[test]
    fn a_file_past_what_is_left_of_the_budget_fails_as_read_in_turn() {
        let dir = tempfile::tempdir().unwrap();
        let mut text = String::from("data\n4 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
        text += "3 1 2 3\n3 1 3 4\n3 1 4 2\n3 2 4 3\n";
        write(dir.path(), "det/t.det", &text);
        let (scene, _) = write(dir.path(), "s.des", "ident\ngetobj t\ngetobj t\n");
        let mut interp = Interpreter::new();
        interp.set_budgets(crate::budget::Budgets {
            polygons: 6,
            ..Default::default()
        });
        let e = interp.execute_file(&scene, true, &mut NoHost).unwrap_err();
        let e = e.to_string();
        assert!(
            e.contains("4 polygons exceed the 2 left of the polygon budget"),
            "{e}"
        );
        assert!(e.contains("t.det:2"), "{e}");
    }

    #[test]
    fn reads_ahead_are_bounded_in_number_per_run() {
        let dir = tempfile::tempdir().unwrap();
        let (p, _) = write(dir.path(), "p.det", &polygon(3, 0.5));
        let mut ahead = ReadAhead::default();
        ahead.start(vec![p.clone(); MAX_STATEMENTS + 10], 100, read_geometry);
        assert_eq!(ahead.by_path[&p].len(), MAX_STATEMENTS);
        ahead.start(vec![p.clone()], 100, read_geometry);
        assert_eq!(ahead.by_path[&p].len(), MAX_STATEMENTS);
        ahead.clear();
        ahead.start(vec![p.clone(); 3], 100, read_geometry);
        assert_eq!(ahead.by_path[&p].len(), 3);
        // Files: past the bound, a statement of a new file is given none
        // (it reads its file itself); one of a file queued shares it.
        ahead.clear();
        let files: Vec<PathBuf> = (0..MAX_READS + 10)
            .map(|k| dir.path().join(format!("{k}.det")))
            .collect();
        let mut paths = files.clone();
        paths.push(files[0].clone());
        assert_eq!(ahead.enqueue(paths, 100, read_geometry), MAX_READS);
        assert_eq!(ahead.by_path.len(), MAX_READS);
        assert_eq!(ahead.by_path[&files[0]].len(), 2);
        assert!(!ahead.by_path.contains_key(&files[MAX_READS]));
    }

    /// Set when the reading of `first.det` below has begun, and when
    /// `second.det` has been read.
    static FIRST_BEGUN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
    static SECOND_READ: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

    /// Reads a file; `first.det` is not finished until `second.det` has
    /// been read (or ten seconds have passed: then it fails).
    fn first_after_second(path: &Path, budget: usize) -> crate::error::Result<Mesh> {
        if path.ends_with("first.det") {
            FIRST_BEGUN.store(true, Ordering::SeqCst);
            let start = std::time::Instant::now();
            while !SECOND_READ.load(Ordering::SeqCst) {
                if start.elapsed().as_secs() >= 10 {
                    return Err(crate::error::Error::Invalid("second never read".into()));
                }
                std::thread::yield_now();
            }
        }
        let mesh = read_geometry(path, budget);
        if path.ends_with("second.det") {
            SECOND_READ.store(true, Ordering::SeqCst);
        }
        mesh
    }

    /// A statement whose file another thread is reading reads the files
    /// queued after it meanwhile: here the only reading thread waits for
    /// the second file, which the statement taking the first reads.
    #[test]
    fn a_statement_waiting_for_its_file_reads_the_next_ones() {
        let dir = tempfile::tempdir().unwrap();
        let (first, _) = write(dir.path(), "first.det", &polygon(3, 0.25));
        let (second, _) = write(dir.path(), "second.det", &polygon(4, 0.25));
        // One reading thread besides the one taking.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(|| {
            let mut ahead = ReadAhead::default();
            ahead.start(vec![first.clone(), second.clone()], 100, first_after_second);
            while !FIRST_BEGUN.load(Ordering::SeqCst) {
                std::thread::yield_now();
            }
            let read = |p: &Path| read_geometry(p, 100).unwrap();
            let taken = |ahead: &mut ReadAhead, p: &Path| ahead.take(p).map(|r| (*r.0).clone());
            assert_eq!(taken(&mut ahead, &first), Some(read(&first)));
            assert_eq!(taken(&mut ahead, &second), Some(read(&second)));
        });
    }

    #[test]
    fn a_read_is_taken_once_by_its_path_and_dropped_when_cleared() {
        let dir = tempfile::tempdir().unwrap();
        let (p, _) = write(dir.path(), "p.det", &polygon(3, 0.5));
        let (q, _) = write(dir.path(), "q.det", &polygon(4, 0.5));
        let bad = dir.path().join("absent.det");
        let mut ahead = ReadAhead::default();
        let paths = vec![p.clone(), q.clone(), bad.clone(), p.clone()];
        ahead.start(paths, 100, read_geometry);
        ahead.settle();
        let read = |p: &Path| read_geometry(p, 100).unwrap();
        let taken = |ahead: &mut ReadAhead, p: &Path| ahead.take(p).map(|r| (*r.0).clone());
        assert_eq!(taken(&mut ahead, &q), Some(read(&q)));
        assert!(ahead.take(&bad).is_none(), "an error is read again in turn");
        assert_eq!(taken(&mut ahead, &p), Some(read(&p)));
        assert_eq!(taken(&mut ahead, &p), Some(read(&p)));
        assert!(ahead.take(&p).is_none(), "two statements queued, two taken");
        // A budget too small for the file: not read ahead.
        ahead.start(vec![q.clone()], 0, read_geometry);
        ahead.settle();
        assert!(ahead.take(&q).is_none());
        // Read but not taken when cleared: a later run reads anew.
        ahead.start(vec![p.clone()], 100, read_geometry);
        ahead.settle();
        ahead.clear();
        assert!(ahead.take(&p).is_none());
    }

    #[test]
    fn statements_reading_one_path_share_one_read_even_one_not_started() {
        let dir = tempfile::tempdir().unwrap();
        let (p, p_h) = write(dir.path(), "p.det", &polygon(5, 0.25));
        let (q, _) = write(dir.path(), "q.det", &polygon(6, 0.25));
        let read = read_geometry(&p, 100).unwrap();
        // Queued, and no thread to read them: the first statement to
        // come reads its file itself, for those after it too.
        let mut ahead = ReadAhead::default();
        let reads = ahead.enqueue(
            vec![p.clone(), q.clone(), p.clone(), p.clone()],
            100,
            read_geometry,
        );
        assert_eq!(reads, 2, "one read a path");
        let count = || contents().iter().filter(|h| **h == p_h).count();
        let before = count();
        let (first, notes) = ahead
            .take(&p)
            .expect("read by the statement that came first");
        assert_eq!(*first, read);
        notes.enter();
        for _ in 0..2 {
            let (mesh, notes) = ahead.take(&p).expect("the same read");
            assert!(Arc::ptr_eq(&mesh, &first));
            notes.enter();
        }
        assert!(ahead.take(&p).is_none(), "three statements, three taken");
        // Each statement enters the file's contents in its own turn.
        assert_eq!(count(), before + 3);
        // With threads reading, the same: one mesh for every statement.
        let mut ahead = ReadAhead::default();
        ahead.start(vec![q.clone(), p.clone(), q.clone()], 100, read_geometry);
        let a = ahead.take(&q).unwrap().0;
        let b = ahead.take(&q).unwrap().0;
        assert!(Arc::ptr_eq(&a, &b));
    }
}

//! ufbx's thread pool on rayon's: the compressed arrays of a binary FBX (most of its bytes)
//! are inflated by rayon's threads while ufbx's parser goes on through the file.
//!
//! ufbx hands out its tasks in up to [`GROUPS`] groups, each a run of task indices
//! (`run_fn`), and later waits for a group (`wait_fn`). Here a group is a range of indices
//! still to run and a count of those running. `run_fn` records the range and spawns a few
//! rayon jobs that take indices from it; `wait_fn` takes indices from it too, on the calling
//! thread, until none is left, then waits for the ones other threads are running. So a load
//! never waits on a job that has not started: inside a busy or one-thread rayon pool (folder
//! mode's files), the waiting thread does the group's work itself.
//!
//! Invariants: a group's indices are each run once (taken under the lock); `wait_fn` returns
//! only when its group has none left to take and none running; the pool's state outlives
//! every job (each holds an `Arc`), and a job only calls into ufbx for an index it took, so a
//! job that starts after the load has returned finds nothing and touches nothing of ufbx's.

use std::ffi::c_void;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};

/// ufbx's `UFBX_THREAD_GROUP_COUNT`: the groups it hands tasks out in.
const GROUPS: usize = 4;

/// A group's task indices: `next..end` still to be taken, `running` taken and not done.
#[derive(Clone, Copy, Default)]
struct Group {
    next: u32,
    end: u32,
    running: u32,
}

/// What `run_fn`, `wait_fn` and the jobs share.
#[derive(Default)]
struct State {
    groups: [Group; GROUPS],
    /// ufbx's context for `ufbx_thread_pool_run_task` (the same for all of one load).
    context: ufbx::ThreadPoolContext,
}

/// The pool of one load, held by [`Pool::options`]' caller for the whole load.
#[derive(Default)]
pub(super) struct Pool {
    state: Mutex<State>,
    /// Signalled when a group's last running task is done.
    done: Condvar,
    /// Tasks run, for the tests to see that a load went through the pool.
    #[cfg(test)]
    ran: std::sync::atomic::AtomicUsize,
}

impl Pool {
    /// ufbx's thread options with this pool. The `Arc` must be kept alive until the load
    /// returns (ufbx waits for every task before it does).
    pub(super) fn options(pool: &Arc<Pool>) -> ufbx::ThreadOpts {
        let raw = ufbx::RawThreadPool {
            init_fn: None,
            run_fn: Some(run),
            wait_fn: Some(wait),
            free_fn: None,
            user: Arc::as_ptr(pool).cast_mut().cast(),
        };
        // SAFETY: `user` points at a `Pool` that the caller keeps alive for the whole load
        // (see above); the functions only read it through shared references.
        let pool = ufbx::ThreadPool::Raw(unsafe { ufbx::Unsafe::new(raw) });
        ufbx::ThreadOpts { pool, ..Default::default() }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic cannot happen under the lock (no ufbx call is made there); take the state
        // as it is if one did.
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Takes one index of `group` to run, marking it running.
    fn take(&self, group: usize) -> Option<(ufbx::ThreadPoolContext, u32)> {
        let mut state = self.lock();
        let context = state.context;
        let g = &mut state.groups[group];
        (g.next < g.end).then(|| {
            g.next += 1;
            g.running += 1;
            (context, g.next - 1)
        })
    }

    /// Runs the indices of `group` this thread can take, until none is left to take.
    fn run_some(&self, group: usize) {
        while let Some((context, index)) = self.take(group) {
            // SAFETY: `index` was handed to `run_fn` for this load's `context` and is run
            // once (taken under the lock); ufbx is waiting for it, so the context is alive.
            unsafe { ufbx::thread_pool_run_task(context, index) };
            #[cfg(test)]
            self.ran.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let mut state = self.lock();
            let g = &mut state.groups[group];
            g.running -= 1;
            if g.running == 0 {
                self.done.notify_all();
            }
        }
    }
}

/// Jobs spawned for a group: enough to keep rayon's other threads busy.
fn jobs(count: u32) -> u32 {
    count.min(u32::try_from(rayon::current_num_threads()).unwrap_or(u32::MAX))
}

/// ufbx's `run_fn`: indices `start..start + count` of `group` are to be run.
unsafe extern "C" fn run(
    user: *mut c_void,
    context: ufbx::ThreadPoolContext,
    group: u32,
    start: u32,
    count: u32,
) {
    // SAFETY: `user` is the `Pool` of `Pool::options`, alive for the load; and a `Pool` is
    // only ever in an `Arc` (`options` takes one), so another strong count can be made.
    let pool = unsafe {
        Arc::increment_strong_count(user.cast::<Pool>().cast_const());
        Arc::from_raw(user.cast::<Pool>().cast_const())
    };
    let group = group as usize % GROUPS;
    {
        let mut state = pool.lock();
        state.context = context;
        state.groups[group] = Group { next: start, end: start + count, running: 0 };
    }
    for _ in 0..jobs(count) {
        let pool = Arc::clone(&pool);
        rayon::spawn(move || pool.run_some(group));
    }
}

/// ufbx's `wait_fn`: returns when every index of `group` has been run.
unsafe extern "C" fn wait(
    user: *mut c_void,
    _context: ufbx::ThreadPoolContext,
    group: u32,
    _max_index: u32,
) {
    // SAFETY: as in `run`; only a shared reference is made.
    let pool = unsafe { &*user.cast::<Pool>().cast_const() };
    let group = group as usize % GROUPS;
    pool.run_some(group);
    let mut state = pool.lock();
    // Nothing is left to take (ufbx calls `run` and `wait` from its one thread): wait for
    // the indices other threads took.
    while state.groups[group].running > 0 {
        state = pool.done.wait(state).unwrap_or_else(|poisoned| poisoned.into_inner());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh as ufbx read it: its faces' corners' positions, normals and UVs, in order.
    type Corners = Vec<([f64; 3], [f64; 3], [f64; 2])>;

    fn meshes(scene: &ufbx::Scene) -> Vec<Corners> {
        let mesh = |m: &ufbx::Mesh| {
            (0..m.num_indices)
                .map(|c| {
                    let p = m.vertex_position[c];
                    let n = if m.vertex_normal.exists { m.vertex_normal[c] } else { p };
                    let uv =
                        if m.vertex_uv.exists { m.vertex_uv[c] } else { ufbx::Vec2::default() };
                    ([p.x, p.y, p.z], [n.x, n.y, n.z], [uv.x, uv.y])
                })
                .collect()
        };
        scene.meshes.iter().map(|m| mesh(m)).collect()
    }

    /// The file loaded without a pool, and with one: the meshes of each, and the tasks the
    /// pool ran.
    fn both(file: &str) -> (Vec<Corners>, Vec<Corners>, usize) {
        let path = format!("{}/../../assets/models/{file}", env!("CARGO_MANIFEST_DIR"));
        let bytes = std::fs::read(&path).unwrap();
        let alone = ufbx::load_memory(&bytes, super::super::scene::load_options()).unwrap();
        let pool = Arc::new(Pool::default());
        let options = ufbx::LoadOpts {
            thread_opts: Pool::options(&pool),
            ..super::super::scene::load_options()
        };
        let pooled = ufbx::load_memory(&bytes, options).unwrap();
        let ran = pool.ran.load(std::sync::atomic::Ordering::Relaxed);
        (meshes(&alone), meshes(&pooled), ran)
    }

    /// Binary FBX files with compressed arrays (inflated by the pool's tasks): the same
    /// meshes as ufbx reads on its own.
    #[test]
    fn a_pooled_load_reads_what_ufbx_alone_reads() {
        for file in
            ["lowpoly/quaternius-ambulance.fbx", "ufbx/blender_279_nested_meshes_7400_binary.fbx"]
        {
            let (alone, pooled, ran) = both(file);
            assert!(ran > 0, "{file}: no task ran in the pool");
            assert!(!alone.is_empty() && alone.iter().all(|m| !m.is_empty()), "{file}");
            assert!(alone == pooled, "{file}: the pooled load read other values");
        }
    }

    /// In a rayon pool of one thread, busy with the load itself, the waiting thread runs the
    /// tasks: the load finishes, with the same meshes.
    #[test]
    fn a_load_in_a_one_thread_pool_does_its_tasks_itself() {
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let (alone, pooled, ran) = one.install(|| both("lowpoly/quaternius-bus.fbx"));
        assert!(ran > 0);
        assert!(alone == pooled);
    }
}

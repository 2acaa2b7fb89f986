//! Work on every core, in order.

use std::sync::atomic::{AtomicUsize, Ordering};

/// The most threads [`parallel_map`] takes (0: every core this process may use); see
/// [`set_threads`].
static THREADS: AtomicUsize = AtomicUsize::new(0);

/// Caps the threads [`parallel_map`] takes from here on, at every level (`cierva evaluate
/// --threads`: an engine's worker given one core runs one evaluation at a time); 0 lifts it.
pub fn set_threads(most: usize) {
    THREADS.store(most, Ordering::Relaxed);
}

/// The threads [`parallel_map`] takes: every core this process may use (its affinity, as a
/// batch scheduler's allocation sets it), or fewer where [`set_threads`] says so.
pub fn threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    match THREADS.load(Ordering::Relaxed) {
        0 => cores,
        most => most,
    }
}

/// `f` over `items` on every core, results in the order of `items`. Items are handed out one at
/// a time as threads come free, so a slow item (a case of 81 tunnel rows) does not hold back a
/// whole chunk; each item runs on one thread, and the output does not depend on the schedule.
pub fn parallel_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = threads().min(items.len().max(1));
    let next = AtomicUsize::new(0);
    let mut out: Vec<(usize, R)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                let (f, next) = (&f, &next);
                s.spawn(move || {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else { break };
                        mine.push((i, f(item)));
                    }
                    mine
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    out.sort_by_key(|(i, _)| *i);
    out.into_iter().map(|(_, r)| r).collect()
}

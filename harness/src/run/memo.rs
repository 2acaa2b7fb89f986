//! What one run computes once and every check asking the same question shares: a process-wide
//! memo of fallible results (failures too: a trim that does not converge is not tried again),
//! keyed by text (an aircraft file's path, a condition and a loading, ...).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// Results by key.
type Remembered<T> = Mutex<HashMap<String, Result<Arc<T>, String>>>;

/// A memo of results by key ([`Memo::get_or`]), holding at most `limit` of them.
pub struct Memo<T>(OnceLock<Remembered<T>>, usize);

impl<T> Default for Memo<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T> Memo<T> {
    /// An empty memo (for a `static`), without a limit.
    pub const fn new() -> Self {
        Self(OnceLock::new(), usize::MAX)
    }

    /// An empty memo that forgets everything it holds when it holds `limit` results: for
    /// results that are a function of their key alone, recomputed the same when asked again,
    /// where nothing else forgets them (a served model's answers, which its client never
    /// tells it to forget).
    pub const fn bounded(limit: usize) -> Self {
        Self(OnceLock::new(), limit)
    }

    /// The result remembered for `key`, or `compute`'s, then remembered. Two threads asking
    /// at once may both compute; the results are the same.
    pub fn get_or(
        &self,
        key: String,
        compute: impl FnOnce() -> Result<T, String>,
    ) -> Result<Arc<T>, String> {
        let map = self.0.get_or_init(Default::default);
        if let Some(hit) = map.lock().ok().and_then(|m| m.get(&key).cloned()) {
            return hit;
        }
        let result = compute().map(Arc::new);
        if let Ok(mut m) = map.lock() {
            if m.len() >= self.1 {
                m.clear();
            }
            m.insert(key, result.clone());
        }
        result
    }

    /// The result remembered for `key`, if there is one.
    pub fn get(&self, key: &str) -> Option<Result<Arc<T>, String>> {
        self.0.get()?.lock().ok()?.get(key).cloned()
    }

    /// Forgets every result whose key starts with `prefix`.
    pub fn forget(&self, prefix: &str) {
        if let Some(Ok(mut m)) = self.0.get().map(|m| m.lock()) {
            m.retain(|k, _| !k.starts_with(prefix));
        }
    }
}

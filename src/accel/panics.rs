//! Panics caught inside a query (an Embree callback, a pure-Rust traversal),
//! kept per scene and reported after the query returns, by `Accel::check`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

#[derive(Default)]
pub(crate) struct PanicSlot {
    happened: AtomicBool,
    first: Mutex<Option<String>>,
}

impl PanicSlot {
    /// Runs `f`; if it panics, records the panic and returns `fallback`. The
    /// cost when nothing panics is one call: no lock, no allocation.
    #[inline]
    pub(crate) fn guard<T>(&self, fallback: T, f: impl FnOnce() -> T) -> T {
        catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|payload| {
            self.record(payload);
            fallback
        })
    }

    pub(crate) fn record(&self, payload: Box<dyn std::any::Any + Send>) {
        let mut first = self.first.lock().unwrap_or_else(|e| e.into_inner());
        first.get_or_insert(describe(payload));
        self.happened.store(true, Ordering::Release);
    }

    /// Whether a panic was recorded since the last `take`: one atomic load,
    /// cheap enough for a render to ask after every sample, so it stops
    /// within the sample after a panic instead of at the end of a pass.
    pub(crate) fn happened(&self) -> bool {
        self.happened.load(Ordering::Acquire)
    }

    /// The first panic since the last call, if any. One atomic load when none happened.
    pub(crate) fn take(&self) -> Option<String> {
        if !self.happened() {
            return None;
        }
        self.happened.store(false, Ordering::Release);
        self.first.lock().unwrap_or_else(|e| e.into_inner()).take()
    }

    /// The first panic since the last check as an internal error naming `what` panicked.
    pub(crate) fn check(&self, what: &str) -> Result<()> {
        match self.take() {
            Some(panic) => Err(Error::Internal(format!("{what} panicked: {panic}"))),
            None => Ok(()),
        }
    }
}

/// A panic's message, when it carries one.
pub(crate) fn describe(payload: Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "no message".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_guarded_panic_is_the_fallback_then_one_error() {
        let slot = PanicSlot::default();
        assert_eq!(slot.guard(0, || 7), 7);
        slot.check("nothing").unwrap();
        assert!(!slot.happened());
        let value: i32 = slot.guard(-1, || panic!("boom {}", 3));
        assert_eq!(value, -1);
        assert!(slot.happened(), "seen before anyone takes it");
        let err = slot.check("the test traversal").unwrap_err();
        assert!(matches!(err, Error::Internal(_)), "{err}");
        assert!(
            err.to_string()
                .contains("the test traversal panicked: boom 3"),
            "{err}"
        );
        assert!(!slot.happened(), "taken by the check");
        slot.check("nothing").unwrap();
    }
}

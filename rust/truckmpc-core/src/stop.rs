//! Stopping long work from outside. The host (the Python binding, which must let Python handle a
//! Ctrl-C or SIGTERM) installs a check for the current thread; the DP asks it once per stage, so
//! even a long solve (a whole-road plan, a very fine grid) ends within a stage's time of a signal.
//! Without a check nothing ever asks to stop.

use std::cell::Cell;

thread_local! {
    static CHECK: Cell<Option<fn() -> bool>> = const { Cell::new(None) };
}

/// Install `check` for this thread (None removes it); returns the one it replaces.
pub fn set_check(check: Option<fn() -> bool>) -> Option<fn() -> bool> {
    CHECK.with(|c| c.replace(check))
}

/// Whether this thread's check asks to stop (false without one).
#[inline]
pub fn requested() -> bool {
    CHECK.with(|c| c.get().is_some_and(|check| check()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No check, no stop; an installed check is asked, and removing it restores the default.
    #[test]
    fn the_installed_check_decides() {
        assert!(!requested());
        assert!(set_check(Some(|| true)).is_none());
        assert!(requested());
        assert!(set_check(None).is_some());
        assert!(!requested());
    }
}

//! Stopping long work from outside. A host that must act while the work runs (the Python binding,
//! which lets Python handle a Ctrl-C or SIGTERM) installs a hook for the work's duration
//! ([`watched`]); the core decides when to ask it, at most every [`CHECK_INTERVAL_S`]: the DP
//! between stages, so even a long solve (a whole-road plan, a very fine grid) ends within a stage's
//! time, and the closed loop between decisions ([`DecisionWatch`]). Once the hook has said stop,
//! the answer stays yes without asking it again. Without a hook nothing asks to stop and no clock
//! is read.

use std::cell::Cell;
use std::time::Instant;

/// The host's question, asked on the working thread: should the work stop now?
pub type Hook = fn() -> bool;

/// The least time between two questions to the hook [s].
pub const CHECK_INTERVAL_S: f64 = 0.05;

/// One-step decisions of the closed loop (a plant step each, well under a microsecond) between two
/// readings of the clock: reading it at every step cost about a tenth of a PI run.
pub const STEPS_PER_CLOCK_READING: u32 = 64;

/// The installed hook, when it was last asked (or installed), and whether it said stop.
#[derive(Clone, Copy)]
struct Watch {
    hook: Hook,
    asked: Instant,
    stop: bool,
}

thread_local! {
    static WATCH: Cell<Option<Watch>> = const { Cell::new(None) };
}

/// Run `work` on this thread with `hook` installed; the watch installed before is restored after,
/// also when `work` panics. The hook is first asked [`CHECK_INTERVAL_S`] after the start.
pub fn watched<T>(hook: Hook, work: impl FnOnce() -> T) -> T {
    struct Restore(Option<Watch>);
    impl Drop for Restore {
        fn drop(&mut self) {
            WATCH.set(self.0);
        }
    }
    let _restore = Restore(WATCH.replace(Some(Watch { hook, asked: Instant::now(), stop: false })));
    work()
}

/// Whether the work on this thread should stop: no without a hook; the hook's answer when
/// [`CHECK_INTERVAL_S`] has passed since it was last asked; yes ever after it said yes.
pub fn requested() -> bool {
    let Some(mut watch) = WATCH.get() else { return false };
    if !watch.stop && watch.asked.elapsed().as_secs_f64() > CHECK_INTERVAL_S {
        // The watch is copied out while the hook runs: a hook may itself run watched work.
        watch.stop = (watch.hook)();
        watch.asked = Instant::now();
        WATCH.set(Some(watch));
    }
    watch.stop
}

/// The closed loop's questions, one after each decision: [`requested`] after every decision held
/// until a distance (a DP solve may have run) and every [`STEPS_PER_CLOCK_READING`] one-step
/// decisions.
#[derive(Debug, Default)]
pub struct DecisionWatch {
    steps: u32,
}

impl DecisionWatch {
    /// Whether the run should stop after a decision, `held` until a distance or for one step.
    #[inline]
    pub fn requested_after(&mut self, held: bool) -> bool {
        self.steps += 1;
        if !held && self.steps < STEPS_PER_CLOCK_READING {
            return false;
        }
        self.steps = 0;
        requested()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::thread::sleep;
    use std::time::Duration;

    thread_local! {
        static ASKED: Cell<u32> = const { Cell::new(0) };
    }

    fn stop_counting() -> bool {
        ASKED.set(ASKED.get() + 1);
        true
    }

    fn go_on_counting() -> bool {
        ASKED.set(ASKED.get() + 1);
        false
    }

    fn past_the_interval() {
        sleep(Duration::from_secs_f64(CHECK_INTERVAL_S * 1.2));
    }

    /// No hook, no stop; the hook is asked once the interval has passed, its yes is kept without
    /// asking again, and the work's end removes it.
    #[test]
    fn the_hook_is_asked_once_per_interval_and_its_stop_is_kept() {
        assert!(!requested());
        watched(stop_counting, || {
            assert!(!requested(), "asked before the interval passed");
            assert_eq!(ASKED.get(), 0);
            past_the_interval();
            assert!(requested() && requested());
            assert_eq!(ASKED.get(), 1);
        });
        assert!(!requested());
    }

    /// The loop asks after every held decision, and after one-step decisions only every
    /// STEPS_PER_CLOCK_READING of them.
    #[test]
    fn the_loop_asks_after_a_hold_or_enough_single_steps() {
        watched(go_on_counting, || {
            let mut watch = DecisionWatch::default();
            past_the_interval();
            assert!(!watch.requested_after(true));
            assert_eq!(ASKED.get(), 1);
            past_the_interval();
            for _ in 1..STEPS_PER_CLOCK_READING {
                assert!(!watch.requested_after(false));
            }
            assert_eq!(ASKED.get(), 1);
            assert!(!watch.requested_after(false));
            assert_eq!(ASKED.get(), 2);
        });
    }

    /// A hook installed inside watched work holds for that work only.
    #[test]
    fn nested_work_restores_the_outer_hook() {
        watched(stop_counting, || {
            watched(go_on_counting, || {
                past_the_interval();
                assert!(!requested());
            });
            assert!(requested(), "the outer hook's interval had passed too");
        });
        assert_eq!(ASKED.get(), 2);
    }
}

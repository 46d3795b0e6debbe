//! SIGINT and SIGTERM: how a command stops when asked, and the error that
//! says it did (`main` maps it to exit 130).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use sturmray::accel::embree::exit_at_once;
use sturmray::error::Error;
use sturmray::io::console::note;

/// A render stopped by SIGINT or SIGTERM after writing what it had.
#[derive(Debug)]
pub struct Interrupted;

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("interrupted")
    }
}

impl std::error::Error for Interrupted {}

/// SIGINT and SIGTERM. During a render the first one stops the render (it
/// drops the pass under way), so the work so far is written; a second ends
/// the process at once. Commands that only write at their end (`trace`,
/// `merge`, `bench`, `accuracy`) end at the first. Never in the middle of
/// writing: the end waits for the files being written, so none is lost or
/// torn and no temporary is left behind.
///
/// A second signal that comes while files are written is answered by the
/// command itself, which asks [`Signals::twice`] before it lets go of the
/// files and then returns [`Interrupted`]: the process ends on the main
/// thread, after everything is released, with exit 130. One that comes at
/// any other time ends the process from the handler's thread with
/// `exit_at_once`, which runs no C++ static destructors: with threads still
/// inside Embree, `std::process::exit` can trip an assertion in Embree's
/// global mutex destructor and abort.
pub struct Signals {
    pub interrupt: Arc<AtomicBool>,
    /// Set by a second signal.
    again: Arc<AtomicBool>,
    /// Set when the command has seen the second signal and will end itself.
    answered: Arc<AtomicBool>,
    writing: Arc<Mutex<()>>,
}

impl Signals {
    /// For a render: the first signal asks it to stop.
    pub fn catch() -> Result<Signals, Error> {
        Self::catch_after(false)
    }

    /// For the other commands that write: the first signal ends the process.
    pub fn catch_at_once() -> Result<Signals, Error> {
        Self::catch_after(true)
    }

    /// `stopping`: as if a first signal had come already.
    fn catch_after(stopping: bool) -> Result<Signals, Error> {
        let interrupt = Arc::new(AtomicBool::new(stopping));
        let again = Arc::new(AtomicBool::new(false));
        let answered = Arc::new(AtomicBool::new(false));
        let writing = Arc::new(Mutex::new(()));
        let (first, second, lock) = (interrupt.clone(), again.clone(), writing.clone());
        let by_command = answered.clone();
        // ctrlc runs this on a thread of its own, so it may wait on a lock.
        ctrlc::set_handler(move || {
            if first.swap(true, Ordering::SeqCst) {
                // Recorded before waiting, so the writer sees it when done.
                second.store(true, Ordering::SeqCst);
                let _writes_done = lock.lock();
                if !by_command.load(Ordering::SeqCst) {
                    exit_at_once(130);
                }
                return;
            }
            note(format_args!(
                "\ninterrupted: stopping, then writing the image of the passes done"
            ));
        })
        .map_err(|e| Error::Internal(format!("cannot catch signals: {e}")))?;
        Ok(Signals {
            interrupt,
            again,
            answered,
            writing,
        })
    }

    /// Held while files are written: a second signal waits for it.
    pub fn writing(&self) -> MutexGuard<'_, ()> {
        self.writing.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Whether a second signal came (while writing, it waits to end the
    /// process: ask before letting go of [`Signals::writing`]). A yes is a
    /// promise: the caller ends the process with [`Interrupted`] itself.
    pub fn twice(&self) -> bool {
        let twice = self.again.load(Ordering::SeqCst);
        if twice {
            self.answered.store(true, Ordering::SeqCst);
        }
        twice
    }
}

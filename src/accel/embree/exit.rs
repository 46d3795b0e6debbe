//! Ending the process at once, from any thread, while other threads may be
//! inside Embree.
//!
//! `std::process::exit` runs the C library's exit handlers, among them
//! libembree's C++ static destructors; if another thread holds one of
//! Embree's global mutexes at that moment (a worker mid-query, the main
//! thread releasing the device), the destructor's assertion aborts the
//! process with SIGABRT instead of the exit status asked for. `_exit` ends
//! the process without running them; the kernel frees everything, and files
//! already renamed into place (see `io::output`) are whole.

use std::io::Write;

/// Flushes Rust's standard streams, then ends the process with `code`,
/// running no exit handlers or static destructors.
pub fn exit_at_once(code: i32) -> ! {
    // Anything printed so far reaches the terminal or pipe: `_exit` does not
    // flush Rust's buffers.
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    // SAFETY: `_exit` takes no pointers and is async-signal-safe; it never
    // returns, so no Rust code runs after it with state it could break.
    unsafe { libc::_exit(code) }
}

//! What commands say on the terminal. Neither a closed stderr nor a reader
//! that stops early (`| head`) is a reason to fail, let alone to panic as
//! `println!` and `eprintln!` do: the command's work is done all the same.

use std::io::Write;

use crate::error::{Error, Result};

/// Says something on stderr (progress, warnings, what was written).
pub fn note(args: std::fmt::Arguments) {
    let _ = writeln!(std::io::stderr(), "{args}");
}

/// Writes a command's report to stdout. A reader gone away (broken pipe)
/// wants no more of it; any other failure is an error.
pub fn print(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(Error::io("standard output", e))
        }
        _ => Ok(()),
    }
}

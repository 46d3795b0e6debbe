//! The subcommands, one module each: its arguments (a clap `Args` struct
//! whose doc comments are its `--help`) and its `run`. What several of them
//! share (the backend choice, loading, the output checks) is in `shared`,
//! the signal handling in `signals`.

pub mod accuracy;
pub mod bench;
pub mod explain;
pub mod info;
pub mod merge;
pub mod render;
pub mod roots;
pub mod shared;
pub mod signals;
pub mod trace;

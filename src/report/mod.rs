//! The studies: benchmarks of the backends and the accuracy study of the
//! root finders (the subcommands that run them are in the binary's `cli`).

pub mod accuracy;
pub mod bench;

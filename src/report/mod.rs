//! Reports for people: scene summaries and benchmarks.

pub mod bench;
pub mod info;
pub mod roots;

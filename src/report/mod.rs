//! Reports for people: scene summaries, benchmarks and the accuracy study.

pub mod accuracy;
pub mod bench;
pub mod info;
pub mod roots;

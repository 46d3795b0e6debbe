//! The proptest settings the fuzz targets share.

use proptest::test_runner::{Config, RngSeed};

/// `cargo test` runs each target on the same `cases` every time, so CI stays
/// deterministic; `make fuzz` sets PROPTEST_CASES and gets fresh random
/// cases on each run (and PROPTEST_RNG_SEED replays a run).
pub fn config(cases: u32) -> Config {
    let mut config = Config::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        config.cases = cases;
        if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
            config.rng_seed = RngSeed::Fixed(6);
        }
    }
    config
}

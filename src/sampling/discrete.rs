//! Picking one of n items in proportion to its weight (lights by power), by
//! a uniform number and a binary search of the running sums.

use super::ONE_MINUS_EPSILON;

/// Running sums of the items' weights; the last is the total.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Discrete {
    cdf: Vec<f32>,
}

impl Discrete {
    /// Negative and NaN weights count as zero.
    pub fn new(weights: impl IntoIterator<Item = f32>) -> Discrete {
        let mut total = 0.0;
        let cdf = weights
            .into_iter()
            .map(|w| {
                total += if w > 0.0 { w } else { 0.0 };
                total
            })
            .collect();
        Discrete { cdf }
    }

    pub fn len(&self) -> usize {
        self.cdf.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cdf.is_empty()
    }

    /// The item for uniform `u` in [0, 1) and the probability of picking it;
    /// None if every weight is zero.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        self.sample_reused(u).map(|(i, p, _)| (i, p))
    }

    /// [`Discrete::sample`], and `u` made uniform in [0, 1) again within the
    /// item's share of it, so the same number can go on to sample the item
    /// (Mitsuba's sample reuse): stratified numbers stay stratified over all
    /// the items together, not only over the choice.
    pub fn sample_reused(&self, u: f32) -> Option<(usize, f32, f32)> {
        let total = *self.cdf.last()?;
        if total <= 0.0 {
            return None;
        }
        let i = self
            .cdf
            .partition_point(|&c| c <= u * total)
            .min(self.cdf.len() - 1);
        let below = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        let reused = (u * total - below) / (self.cdf[i] - below);
        Some((i, self.probability(i), reused.clamp(0.0, ONE_MINUS_EPSILON)))
    }

    /// The probability of picking item i.
    pub fn probability(&self, i: usize) -> f32 {
        let total = self.cdf.last().copied().unwrap_or(0.0);
        if total <= 0.0 {
            return 0.0;
        }
        let below = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        (self.cdf[i] - below) / total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_are_picked_by_weight() {
        let d = Discrete::new([1.0, 0.0, 3.0, -2.0]);
        assert_eq!(d.len(), 4);
        assert_eq!(d.sample(0.1), Some((0, 0.25)));
        assert_eq!(d.sample(0.5), Some((2, 0.75)));
        // u just below 1 stays in range and never lands on a zero weight.
        assert_eq!(d.sample(0.999_999_9), Some((2, 0.75)));
        assert_eq!(d.probability(1), 0.0);
        assert_eq!(d.probability(3), 0.0);
        assert_eq!(Discrete::new([0.0, 0.0]).sample(0.5), None);
        assert!(Discrete::new([]).is_empty());
        assert_eq!(Discrete::new([]).sample(0.5), None);
    }

    #[test]
    fn the_reused_number_spans_the_unit_interval_within_each_item() {
        let d = Discrete::new([1.0, 0.0, 3.0]);
        assert_eq!(d.sample_reused(0.0), Some((0, 0.25, 0.0)));
        assert_eq!(d.sample_reused(0.125), Some((0, 0.25, 0.5)));
        assert_eq!(d.sample_reused(0.25), Some((2, 0.75, 0.0)));
        assert_eq!(d.sample_reused(0.625), Some((2, 0.75, 0.5)));
        // Evenly spread numbers stay evenly spread within each item: the 120
        // of 160 that fall in [0.25, 1) land in 120 different 120ths once reused.
        let mut seen = [false; 120];
        for k in 0..160 {
            let (i, _, r) = d.sample_reused((k as f32 + 0.5) / 160.0).unwrap();
            assert!((0.0..1.0).contains(&r));
            if i == 2 {
                assert!(!std::mem::replace(&mut seen[(r * 120.0) as usize], true));
            }
        }
        assert!(seen.iter().all(|&s| s));
        let top = d.sample_reused(0.999_999_9).unwrap();
        assert!(top.0 == 2 && top.2 < 1.0, "{top:?}");
    }
}

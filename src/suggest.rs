//! "Did you mean ...?": the closest known name to a likely typo, for scene
//! keys, material names and the names in algebraic expressions.

/// The candidate closest to `word`, if close enough to be a likely typo (at
/// most a third of its length, and at least 2, edits away). Ties go to a
/// candidate that differs only in case (`X` → `x`), then to the earlier one.
pub fn closest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (word.chars().count() / 3).max(2);
    candidates
        .into_iter()
        .enumerate()
        .map(|(i, c)| {
            (
                strsim::levenshtein(word, c),
                !c.eq_ignore_ascii_case(word),
                i,
                c,
            )
        })
        .filter(|&(d, ..)| d <= limit)
        .min()
        .map(|(.., c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_names() {
        assert_eq!(closest("rr", ["x", "y", "z", "R", "r"]), Some("r"));
        assert_eq!(closest("X", ["x", "y", "z"]), Some("x"));
        assert_eq!(closest("alpah", ["x", "alpha"]), Some("alpha"));
        assert_eq!(closest("banana", ["x", "y", "z"]), None);
        assert_eq!(closest("lookat", ["eye", "look_at"]), Some("look_at"));
    }
}

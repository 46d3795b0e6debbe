//! "Did you mean ...?": the closest known name to a likely typo, for scene
//! keys, material names and the names in algebraic expressions, and the hint
//! added to serde's "unknown field" and "unknown variant" messages.

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

/// Appends a suggestion to serde's "unknown field `x`, expected one of `a`, `b`"
/// (or "unknown variant ...") message, when one candidate is close.
pub fn with_suggestion(message: &str) -> String {
    let hint = (|| {
        let start = message
            .find("unknown field `")
            .or_else(|| message.find("unknown variant `"))?;
        let rest = &message[start..];
        let open = rest.find('`')? + 1;
        let close = open + rest[open..].find('`')?;
        let word = &rest[open..close];
        let expected = &rest[close + 1..];
        let candidates = expected.split('`').skip(1).step_by(2);
        closest(word, candidates).map(|c| format!("did you mean `{c}`?"))
    })();
    match hint {
        Some(hint) => format!("{}\n{hint}", message.trim_end()),
        None => message.to_owned(),
    }
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

    #[test]
    fn suggests_only_close_keys() {
        let msg = "unknown field `lookat`, expected one of `eye`, `look_at`, `up`, `fov`";
        assert!(with_suggestion(msg).ends_with("did you mean `look_at`?"));
        let far = "unknown field `zebra`, expected one of `eye`, `look_at`";
        assert_eq!(with_suggestion(far), far);
        let variant = "unknown variant `pont`, expected `point` or `directional`";
        assert!(with_suggestion(variant).ends_with("did you mean `point`?"));
    }
}

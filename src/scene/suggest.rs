//! "Did you mean ...?" for unknown keys and variants in scene files.

/// Levenshtein distance between two short strings.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diagonal + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// The closest candidate, if it is close enough to be a likely typo.
pub fn closest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (word.chars().count() / 3).max(2);
    candidates
        .into_iter()
        .map(|c| (edit_distance(word, c), c))
        .filter(|&(d, _)| d <= limit)
        .min()
        .map(|(_, c)| c)
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
    fn distances() {
        assert_eq!(edit_distance("fov", "fov"), 0);
        assert_eq!(edit_distance("fvo", "fov"), 2);
        assert_eq!(edit_distance("look_At", "look_at"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
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

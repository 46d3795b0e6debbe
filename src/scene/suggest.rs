//! "Did you mean ...?" for the unknown keys and variants serde reports in scene files.

pub use crate::suggest::closest;

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
    fn suggests_only_close_keys() {
        let msg = "unknown field `lookat`, expected one of `eye`, `look_at`, `up`, `fov`";
        assert!(with_suggestion(msg).ends_with("did you mean `look_at`?"));
        let far = "unknown field `zebra`, expected one of `eye`, `look_at`";
        assert_eq!(with_suggestion(far), far);
        let variant = "unknown variant `pont`, expected `point` or `directional`";
        assert!(with_suggestion(variant).ends_with("did you mean `point`?"));
    }
}

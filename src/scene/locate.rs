//! Finds where a key path such as `objects[2].transform.scale` sits in a TOML
//! file, so errors found after parsing still name their line.

use toml::de::{DeTable, DeValue};

/// One step of a key path: a table key, optionally indexing an array.
fn steps(path: &str) -> impl Iterator<Item = (&str, Option<usize>)> {
    path.split('.').map(|step| match step.split_once('[') {
        Some((key, rest)) => (key, rest.trim_end_matches(']').parse().ok()),
        None => (step, None),
    })
}

/// The 1-based line of `path` in `text`, or of the deepest part of it that
/// exists (a key left out, and so defaulted, is reported at its table).
pub fn line_of(text: &str, path: &str) -> Option<usize> {
    let root = DeTable::parse(text).ok()?;
    let mut table: &DeTable = root.get_ref();
    let mut offset = None;
    for (key, index) in steps(path) {
        let Some((k, v)) = table.iter().find(|(k, _)| k.get_ref().as_ref() == key) else {
            break;
        };
        offset = Some(k.span().start);
        let mut value = v;
        if let Some(i) = index {
            let DeValue::Array(items) = value.get_ref() else {
                break;
            };
            let Some(item) = items.get(i) else {
                break;
            };
            offset = Some(item.span().start);
            value = item;
        }
        match value.get_ref() {
            DeValue::Table(t) => table = t,
            _ => break,
        }
    }
    offset.map(|o| text[..o].matches('\n').count() + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "\
background = [0, 0, 0]

[camera]
eye = [0, 0, 1]
fov = 0

[[objects]]
type = \"mesh\"

[[objects]]
type = \"sphere\"
transform = { scale = 0 }
";

    #[test]
    fn finds_keys_tables_and_array_items() {
        assert_eq!(line_of(TEXT, "background"), Some(1));
        assert_eq!(line_of(TEXT, "camera.fov"), Some(5));
        assert_eq!(line_of(TEXT, "objects[1].transform.scale"), Some(12));
        assert_eq!(
            line_of(TEXT, "objects[0]"),
            Some(7),
            "the [[objects]] header"
        );
        // A key that is not there: its table's line.
        assert_eq!(line_of(TEXT, "camera.width"), Some(3));
        assert_eq!(line_of(TEXT, "render.spp"), None);
    }
}

//! ARCHITECTURE.md's module map matches the code: every module it lists
//! exists, every top-level module of the library and of the binary is
//! listed, and no module uses one listed above it (the map lists the highest
//! layer first, so every dependency points down the page).
//!
//! The map is the code block between `<!-- module-map:start -->` and
//! `<!-- module-map:end -->`. A row starts at the left margin with a module
//! name (`main.rs`, a top-level module `x`, or a submodule `x::y`, which is
//! only checked to exist); indented lines continue the row above.

use std::fs;
use std::path::{Path, PathBuf};

const START: &str = "<!-- module-map:start -->";
const END: &str = "<!-- module-map:end -->";

/// The module names of the map, in order, top of the page first.
fn parse_map(doc: &str) -> Result<Vec<String>, String> {
    let start = doc.find(START).ok_or("no module-map:start marker")?;
    let end = doc[start..].find(END).ok_or("no module-map:end marker")? + start;
    let rows: Vec<String> = doc[start + START.len()..end]
        .lines()
        .filter(|line| !line.starts_with("```") && !line.starts_with(char::is_whitespace))
        .filter_map(|line| line.split_whitespace().next())
        .map(str::to_owned)
        .collect();
    if rows.is_empty() {
        return Err("the module map has no rows".into());
    }
    Ok(rows)
}

/// The top-level modules a source text names in code after one of
/// `prefixes`. Comment lines are skipped: a doc link is not a dependency.
fn used_modules(source: &str, prefixes: &[&str]) -> Vec<String> {
    let mut used = Vec::new();
    for line in source.lines() {
        if line.trim_start().starts_with("//") {
            continue;
        }
        let found = prefixes
            .iter()
            .flat_map(|&prefix| line.match_indices(prefix).map(move |(at, _)| (at, prefix)));
        for (at, prefix) in found {
            let rest = &line[at + prefix.len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() && !used.contains(&name) {
                used.push(name);
            }
        }
    }
    used
}

/// Everything wrong with `map` against the crate: rows that name no module
/// (`exists`), modules `lib.rs` (`declared`) or `main.rs` (`binary`)
/// declares that the map leaves out, and uses that run upward. `sources`
/// pairs each top-level row with the text of its files.
fn problems(
    map: &[String],
    exists: impl Fn(&str) -> bool,
    declared: &[String],
    binary: &[String],
    sources: &[(String, String)],
) -> Vec<String> {
    let mut found = Vec::new();
    for row in map {
        if !exists(row) {
            found.push(format!("the map lists `{row}`, which is not in src/"));
        }
    }
    let files = [("lib.rs", declared), ("main.rs", binary)];
    for (file, modules) in files {
        for module in modules {
            if !map.contains(module) {
                found.push(format!(
                    "`{module}` is declared in {file} but not in the map"
                ));
            }
        }
    }
    let position = |name: &str| map.iter().position(|row| row == name);
    for (module, source) in sources {
        let Some(own) = position(module) else {
            continue;
        };
        // The binary names the library's modules `sturmray::x` and its own
        // `crate::x`.
        let prefixes: &[&str] = if module == "main.rs" || binary.contains(module) {
            &["sturmray::", "crate::"]
        } else {
            &["crate::"]
        };
        for used in used_modules(source, prefixes) {
            if let Some(at) = position(&used)
                && at < own
            {
                found.push(format!(
                    "`{module}` uses `{used}`, which the map lists above it"
                ));
            }
        }
    }
    found
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Whether a map row names a module file: `main.rs`, `x` as `x.rs` or
/// `x/mod.rs`, `x::y` as `x/y.rs` or `x/y/mod.rs`.
fn module_exists(row: &str) -> bool {
    if row == "main.rs" {
        return src().join(row).is_file();
    }
    let dir = src().join(row.replace("::", "/"));
    dir.with_extension("rs").is_file() || dir.join("mod.rs").is_file()
}

/// The text of every `.rs` file of a top-level module (its file and its
/// folder, recursively).
fn module_source(row: &str) -> String {
    fn collect(dir: &Path, into: &mut String) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        let mut paths: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
        paths.sort();
        for path in paths {
            if path.is_dir() {
                collect(&path, into);
            } else if path.extension().is_some_and(|e| e == "rs") {
                into.push_str(&fs::read_to_string(&path).unwrap());
            }
        }
    }
    if row == "main.rs" {
        return fs::read_to_string(src().join(row)).unwrap();
    }
    let mut text = fs::read_to_string(src().join(row).with_extension("rs")).unwrap_or_default();
    collect(&src().join(row), &mut text);
    text
}

/// The modules `file` (in src/) declares, its lines that start with `keyword`.
fn declared_modules(file: &str, keyword: &str) -> Vec<String> {
    fs::read_to_string(src().join(file))
        .unwrap()
        .lines()
        .filter_map(|line| line.strip_prefix(keyword))
        .map(|rest| rest.trim_end_matches(';').to_owned())
        .collect()
}

#[test]
fn the_module_map_matches_the_code() {
    let doc =
        fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md")).unwrap();
    let map = parse_map(&doc).unwrap();
    let declared = declared_modules("lib.rs", "pub mod ");
    assert!(!declared.is_empty(), "lib.rs declares no modules");
    let binary = declared_modules("main.rs", "mod ");
    let sources: Vec<(String, String)> = map
        .iter()
        .filter(|row| !row.contains("::"))
        .map(|row| (row.clone(), module_source(row)))
        .collect();
    let found = problems(&map, module_exists, &declared, &binary, &sources);
    assert!(found.is_empty(), "ARCHITECTURE.md:\n{}", found.join("\n"));
}

// The check itself, on small made-up maps: it must be able to fail.

const FAKE: &str = "intro\n<!-- module-map:start -->\n```\nmain.rs   the CLI\nrender    the loop\n          over tiles\nrender::plan  which effects\nmath      vectors\n```\n<!-- module-map:end -->\n";

fn fake(rows: &[&str]) -> Vec<String> {
    rows.iter().map(|r| (*r).to_owned()).collect()
}

#[test]
fn the_parser_reads_rows_and_skips_continuations() {
    assert_eq!(
        parse_map(FAKE).unwrap(),
        fake(&["main.rs", "render", "render::plan", "math"])
    );
    assert!(parse_map("no markers").is_err());
}

#[test]
fn a_downward_use_passes_and_an_upward_one_fails() {
    let map = parse_map(FAKE).unwrap();
    let declared = fake(&["render", "math"]);
    let down = [
        ("main.rs".to_owned(), "use sturmray::render;".to_owned()),
        ("render".to_owned(), "use crate::math::Ray;".to_owned()),
        ("math".to_owned(), "// see crate::render\n".to_owned()),
    ];
    assert_eq!(
        problems(&map, |_| true, &declared, &[], &down),
        Vec::<String>::new()
    );
    let up = [(
        "math".to_owned(),
        "let x = crate::render::run();".to_owned(),
    )];
    assert_eq!(
        problems(&map, |_| true, &declared, &[], &up),
        ["`math` uses `render`, which the map lists above it"]
    );
}

#[test]
fn a_missing_or_unlisted_module_fails() {
    let map = parse_map(FAKE).unwrap();
    let found = problems(
        &map,
        |row| row != "render::plan",
        &fake(&["render", "math", "film"]),
        &[],
        &[],
    );
    assert_eq!(
        found,
        [
            "the map lists `render::plan`, which is not in src/",
            "`film` is declared in lib.rs but not in the map",
        ]
    );
}

#[test]
fn the_binary_is_checked_through_both_of_its_prefixes() {
    let map = parse_map(&FAKE.replace("math      vectors", "cli   subcommands\nmath      vectors"))
        .unwrap();
    let declared = fake(&["render", "math"]);
    let down = [(
        "cli".to_owned(),
        "use sturmray::math::Ray;\nuse crate::cli::shared;".to_owned(),
    )];
    assert_eq!(
        problems(&map, |_| true, &declared, &fake(&["cli"]), &down),
        Vec::<String>::new()
    );
    // Only the binary names the library `sturmray::`: in a library module
    // that text is not a use.
    let up = [
        ("cli".to_owned(), "use sturmray::render::job;".to_owned()),
        (
            "math".to_owned(),
            "// sturmray::render\nsturmray::render".to_owned(),
        ),
    ];
    assert_eq!(
        problems(&map, |_| true, &declared, &fake(&["cli", "signals"]), &up),
        [
            "`signals` is declared in main.rs but not in the map",
            "`cli` uses `render`, which the map lists above it",
        ]
    );
}

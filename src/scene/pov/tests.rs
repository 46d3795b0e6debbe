//! Unit tests of the POV-Ray reader.

use super::parse::Parser;
use super::value::Value;

fn parser(text: &str) -> (tempfile::TempDir, Parser) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.pov");
    std::fs::write(&path, text).unwrap();
    let p = Parser::new(&path, &[], (800, 600)).unwrap();
    (dir, p)
}

#[test]
fn debug_declare() {
    let (_d, mut p) = parser("#declare MF = finish { ambient 0.1 }\n#declare T = texture { finish { MF } }");
    while p.peek().unwrap().is_some() {
        p.next().unwrap();
    }
    eprintln!("{:?} {:?}", p.symbol("T"), p.warnings);
    assert!(matches!(p.symbol("MF"), Some(Value::Finish(_))));
}

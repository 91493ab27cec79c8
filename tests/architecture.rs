//! ARCHITECTURE.md's module map names every file under `src/`: a module added without a line
//! in the map fails here.

use std::path::{Path, PathBuf};

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("read src") {
        let p = e.expect("dir entry").path();
        if p.is_dir() {
            files(&p, out);
        } else {
            out.push(p);
        }
    }
}

/// The map's rows: the backticked path in the first column, and every backticked word in the
/// second.
fn rows(map: &str) -> Vec<(String, Vec<String>)> {
    let ticked = |s: &str| -> Vec<String> { s.split('`').skip(1).step_by(2).map(str::to_string).collect() };
    map.lines()
        .filter(|l| l.starts_with("| `"))
        .filter_map(|l| {
            let mut cols = l.split('|').skip(1);
            let path = ticked(cols.next()?).into_iter().next()?;
            Some((path, ticked(cols.next().unwrap_or(""))))
        })
        .collect()
}

#[test]
fn every_source_file_is_in_the_module_map() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("read ARCHITECTURE.md");
    let map = &doc[doc.find("## Modules").expect("a Modules section")..];
    let map = &map[..map[3..].find("\n## ").map_or(map.len(), |i| i + 3)];
    let rows = rows(map);
    assert!(rows.len() > 10, "the map has rows");
    let mut all = Vec::new();
    files(&root.join("src"), &mut all);
    let mut missing = Vec::new();
    for f in &all {
        let rel = f
            .strip_prefix(root)
            .expect("under the root")
            .to_string_lossy()
            .replace('\\', "/");
        let name = f.file_name().expect("a name").to_string_lossy().to_string();
        let dir = format!("{}/", rel[..rel.len() - name.len()].trim_end_matches('/'));
        // Named by its own row, or by name in the row of its folder.
        let named = rows
            .iter()
            .any(|(path, words)| *path == rel || (*path == dir && words.contains(&name)));
        if !named {
            missing.push(rel);
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md's module map does not name: {missing:?}"
    );
    assert!(all.len() > 50, "found the sources ({})", all.len());
}

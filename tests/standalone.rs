//! The repository stands alone (issue 13, item 15): no file a user gets refers to a path
//! outside it (the sibling folder the project was started from), and the method is written down inside it.

use std::path::Path;

fn walk(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        if p.is_dir() {
            if !["target", ".git", "out", "build", "build-asan", "dist"].contains(&name.as_str()) {
                walk(&p, out);
            }
        } else if [
            ".rs", ".md", ".sh", ".h", ".hpp", ".c", ".cpp", ".toml", ".cs", ".wgsl", ".py",
        ]
        .iter()
        .any(|x| name.ends_with(x))
        {
            out.push(p);
        }
    }
}

#[test]
fn no_file_refers_outside_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    walk(root, &mut files);
    assert!(files.len() > 50, "walked {} files", files.len());
    // Spelled in two halves so that this file does not match itself.
    let needles = [
        format!("../{}", "shared"),
        format!("{}/peers", "shared"),
        format!("{}/METHOD", "shared"),
    ];
    let mut hits = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap_or_default();
        for n in &needles {
            if text.contains(n.as_str()) {
                hits.push(format!("{} mentions {n}", f.strip_prefix(root).unwrap().display()));
            }
        }
    }
    assert!(hits.is_empty(), "{hits:#?}");
    let method = std::fs::read_to_string(root.join("docs/METHOD.md")).unwrap();
    for eq in ["(1)", "(2)", "(3)", "(4)", "(5)"] {
        assert!(method.contains(eq), "docs/METHOD.md lacks equation {eq}");
    }
}

//! Tidiness of the tree itself, in the manner of rust-analyzer's `tidy`:
//! the crate layering, the size of source files, references from code
//! and docs to files that exist, and test files that their test binary
//! compiles.
//!
//! These tests read the repository, not the model: they fail when a change
//! adds an upward crate edge, a file too long to hold in mind, a pointer
//! to a document that is not there, or a test file that would never run.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The workspace root (this package is the root package).
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every file under `dir` (recursively) whose name ends with `ext`, skipping
/// build outputs and hidden folders.
fn files_with(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with('.') || name == "target" || name == "validation" {
            continue;
        }
        if path.is_dir() {
            files_with(&path, ext, out);
        } else if name.ends_with(ext) {
            out.push(path);
        }
    }
}

/// The layering of ARCHITECTURE.md: for each workspace crate, the project
/// crates its library code may depend on. Everything not listed is refused,
/// so a new edge is a decision written here, not an accident.
fn allowed_edges() -> BTreeMap<&'static str, BTreeSet<&'static str>> {
    let layers: [(&str, &[&str]); 12] = [
        ("tyreroad-core", &[]),
        ("tyreroad-asperity", &["tyreroad-core"]),
        (
            "tyreroad-contact-law",
            &["tyreroad-core", "tyreroad-asperity"],
        ),
        (
            "tyreroad-multipoint",
            &["tyreroad-core", "tyreroad-asperity", "tyreroad-contact-law"],
        ),
        ("tyreroad-texture", &["tyreroad-core", "tyreroad-asperity"]),
        (
            "tyreroad-rolling",
            &[
                "tyreroad-core",
                "tyreroad-asperity",
                "tyreroad-contact-law",
                "tyreroad-multipoint",
            ],
        ),
        ("tyreroad-bem", &["tyreroad-core"]),
        // The hereditary solve steps the elastic multipoint solver; its
        // reference steps the elastic BEM; viscoelastic rolling steps the
        // rolling crate's road, footprint selection and records.
        (
            "tyreroad-viscoelastic",
            &[
                "tyreroad-core",
                "tyreroad-asperity",
                "tyreroad-contact-law",
                "tyreroad-multipoint",
                "tyreroad-bem",
                "tyreroad-rolling",
            ],
        ),
        ("tyreroad-film", &["tyreroad-core"]),
        (
            "tyreroad",
            &[
                "tyreroad-core",
                "tyreroad-asperity",
                "tyreroad-contact-law",
                "tyreroad-multipoint",
                "tyreroad-texture",
                "tyreroad-rolling",
                "tyreroad-bem",
                "tyreroad-film",
                "tyreroad-viscoelastic",
            ],
        ),
        // Above the facade: MPI rolling and sweeps run scenarios
        // (docs/distributed.md); the rolling crate for its records.
        ("tyreroad-distributed", &["tyreroad", "tyreroad-rolling"]),
        // The runner reaches the model through the facade, and runs
        // sweeps and MPI jobs through the distributed layer above it.
        ("xtask", &["tyreroad", "tyreroad-distributed"]),
    ];
    layers
        .into_iter()
        .map(|(name, deps)| (name, deps.iter().copied().collect()))
        .collect()
}

/// `(package, dependency, kind)` for every project-internal dependency,
/// from `cargo metadata`.
fn internal_edges() -> Vec<(String, String, String)> {
    let output = Command::new(env!("CARGO"))
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(root())
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "cargo metadata failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = String::from_utf8(output.stdout).expect("metadata is UTF-8");
    let metadata: serde_json::Value = serde_json::from_str(&text).expect("metadata is JSON");
    let packages = metadata["packages"].as_array().expect("packages");
    let names: BTreeSet<&str> = packages.iter().filter_map(|p| p["name"].as_str()).collect();
    let mut edges = Vec::new();
    for package in packages {
        let name = package["name"].as_str().expect("package name");
        for dep in package["dependencies"].as_array().expect("dependencies") {
            let dep_name = dep["name"].as_str().expect("dependency name");
            if names.contains(dep_name) {
                let kind = dep["kind"].as_str().unwrap_or("normal").to_string();
                edges.push((name.to_string(), dep_name.to_string(), kind));
            }
        }
    }
    edges
}

#[test]
fn crate_edges_follow_the_layering() {
    let allowed = allowed_edges();
    let mut packages = BTreeSet::new();
    let mut violations = Vec::new();
    for (package, dep, kind) in internal_edges() {
        packages.insert(package.clone());
        let Some(ok) = allowed.get(package.as_str()) else {
            violations.push(format!("{package} is not in the layering of tests/tidy.rs"));
            continue;
        };
        // Tests and benchmarks may reach one layer up to check against
        // it (texture's tests build laws from its caps); libraries may not.
        if kind == "dev" {
            continue;
        }
        if !ok.contains(dep.as_str()) {
            violations.push(format!("{package} -> {dep} ({kind})"));
        }
    }
    assert!(
        violations.is_empty(),
        "crate edges outside the layering:\n{}",
        violations.join("\n")
    );
}

/// Longest source file, in lines: one a reader can hold in mind.
const MAX_LINES: usize = 800;

#[test]
fn no_source_file_is_longer_than_800_lines() {
    let mut files = Vec::new();
    for dir in ["crates", "src", "xtask", "tests", "benches", "examples"] {
        files_with(&root().join(dir), ".rs", &mut files);
    }
    assert!(files.len() > 50, "found only {} source files", files.len());
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let lines = fs::read_to_string(f).ok()?.lines().count();
            (lines > MAX_LINES).then(|| format!("{} ({lines} lines)", f.display()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "files over {MAX_LINES} lines:\n{}",
        long.join("\n")
    );
}

/// The repository-relative paths a text points at: `docs/….md`,
/// `fixtures/…`, and, in Markdown (`markdown`), the targets of relative
/// links `](…)` (in Rust sources those are rustdoc's intra-doc links, which
/// `cargo doc -D warnings` checks).
fn referenced_paths(text: &str, from_dir: &Path, markdown: bool) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for prefix in ["docs/", "fixtures/"] {
        let mut rest = text;
        while let Some(at) = rest.find(prefix) {
            // Only whole path tokens: `docs/x.md`, not `mydocs/`.
            let before = rest[..at].chars().last();
            let tail = &rest[at..];
            let end = tail
                .find(|c: char| !(c.is_ascii_alphanumeric() || "/_-.".contains(c)))
                .unwrap_or(tail.len());
            let token = tail[..end].trim_end_matches('.');
            let whole = !before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == '/');
            if whole && token.contains('.') && !token.ends_with('/') {
                out.push(root().join(token));
            }
            rest = &tail[end.max(1)..];
        }
    }
    let mut rest = if markdown { text } else { "" };
    while let Some(at) = rest.find("](") {
        let tail = &rest[at + 2..];
        let end = tail.find(')').unwrap_or(tail.len());
        let target = tail[..end].split('#').next().unwrap_or("");
        if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
            out.push(from_dir.join(target));
        }
        rest = &tail[end.min(tail.len())..];
    }
    out
}

#[test]
fn docs_and_comments_point_at_files_that_exist() {
    let mut files = Vec::new();
    for dir in [
        "crates", "src", "xtask", "tests", "benches", "examples", "docs", "fixtures",
    ] {
        files_with(&root().join(dir), ".rs", &mut files);
        files_with(&root().join(dir), ".md", &mut files);
        files_with(&root().join(dir), ".toml", &mut files);
    }
    for top in ["README.md", "ARCHITECTURE.md"] {
        files.push(root().join(top));
    }
    let mut dangling = Vec::new();
    for file in &files {
        let Ok(text) = fs::read_to_string(file) else {
            continue;
        };
        let dir = file.parent().unwrap_or(&root()).to_path_buf();
        // This file quotes the patterns it looks for.
        if file.ends_with("tests/tidy.rs") {
            continue;
        }
        let markdown = file.extension().is_some_and(|e| e == "md");
        for target in referenced_paths(&text, &dir, markdown) {
            if !target.exists() {
                dangling.push(format!("{} -> {}", file.display(), target.display()));
            }
        }
        // DESIGN.md lives outside the repository: a reader cannot follow it.
        if text.contains("DESIGN §") || text.contains("DESIGN.md") {
            dangling.push(format!(
                "{} cites DESIGN, which is not in the repository",
                file.display()
            ));
        }
    }
    assert!(
        dangling.is_empty(),
        "references to files that do not exist:\n{}",
        dangling.join("\n")
    );
}

#[test]
fn the_reference_scanner_finds_paths_and_links() {
    let text = "see docs/theory.md, [a](../README.md#x) and mydocs/x.md, https://x.y/docs/z.md";
    let found = referenced_paths(text, &root().join("docs"), true);
    assert_eq!(
        found,
        vec![
            root().join("docs/theory.md"),
            root().join("docs").join("../README.md")
        ]
    );
}

/// A package with `autotests = false` builds its tests from
/// `tests/integration.rs` alone (ARCHITECTURE.md, "Workspace level"): a test
/// file there without its `mod` line would never be compiled nor run, and
/// nothing else would say so.
#[test]
fn every_test_file_is_a_module_of_its_integration_binary() {
    let mut manifests = vec![root().join("Cargo.toml"), root().join("xtask/Cargo.toml")];
    for entry in fs::read_dir(root().join("crates"))
        .expect("crates/ is readable")
        .flatten()
    {
        manifests.push(entry.path().join("Cargo.toml"));
    }
    let mut merged = 0;
    let mut missing = Vec::new();
    for manifest in manifests {
        let Ok(text) = fs::read_to_string(&manifest) else {
            continue;
        };
        if !text.lines().any(|l| l.trim() == "autotests = false") {
            continue;
        }
        merged += 1;
        let tests = manifest
            .parent()
            .expect("a manifest is in a folder")
            .join("tests");
        let hub = fs::read_to_string(tests.join("integration.rs")).expect("tests/integration.rs");
        let declared: BTreeSet<&str> = hub
            .lines()
            .filter_map(|l| l.trim().strip_prefix("mod ")?.strip_suffix(';'))
            .collect();
        for entry in fs::read_dir(&tests).expect("tests/ is readable").flatten() {
            let path = entry.path();
            let module = if path.is_dir() && path.join("mod.rs").is_file() {
                entry.file_name().to_string_lossy().into_owned()
            } else if path.extension().is_some_and(|e| e == "rs") {
                path.file_stem()
                    .expect("a file name")
                    .to_string_lossy()
                    .into_owned()
            } else {
                continue;
            };
            if module != "integration" && !declared.contains(module.as_str()) {
                missing.push(path.display().to_string());
            }
        }
    }
    assert_eq!(merged, 5, "packages with one integration binary");
    assert!(
        missing.is_empty(),
        "not a `mod` of tests/integration.rs: {missing:?}"
    );
}

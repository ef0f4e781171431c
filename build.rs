//! Embeds every ground-motion file in `records/` (and its sub-folders, e.g. the FEMA P695
//! suites in `records/fema-p695/<set>/`) into the binary, so a `rocklab` copied to a cluster
//! node still knows the shipped records. Dropping a new file into `records/` and rebuilding
//! embeds it too: no code change. Files in sub-folders are named by their path relative to
//! `records/` with `/` separators (`fema-p695/farfield/index.csv`).

use std::fmt::Write as _;
use std::path::Path;

/// File kinds the record reader understands, plus the indexes (`index.ron`, a suite's
/// `index.csv`).
fn is_record_file(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower == "index.ron"
        || [".at2", ".txt", ".csv", ".dat", ".acc"]
            .iter()
            .any(|ext| lower.ends_with(ext))
}

/// Relative names (with `/`) of every record file under `dir`, sub-folders included.
fn collect(dir: &Path, prefix: &str, out: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.filter_map(Result::ok) {
        let Ok(name) = entry.file_name().into_string() else {
            continue;
        };
        let path = entry.path();
        if path.is_dir() {
            println!("cargo:rerun-if-changed={}", path.display());
            collect(&path, &format!("{prefix}{name}/"), out);
        } else if path.is_file() && is_record_file(&name) {
            out.push(format!("{prefix}{name}"));
        }
    }
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("records");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut names = Vec::new();
    collect(&dir, "", &mut names);
    names.sort();
    let mut code =
        String::from("/// (file name, contents) of each file embedded from `records/`.\n");
    code.push_str("pub static EMBEDDED: &[(&str, &str)] = &[\n");
    for name in &names {
        let path = dir.join(name);
        writeln!(
            code,
            "    ({name:?}, include_str!({:?})),",
            path.display().to_string()
        )
        .unwrap();
    }
    code.push_str("];\n");
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .join("embedded_records.rs");
    std::fs::write(out, code).expect("OUT_DIR is writable");
}

//! Embeds every ground-motion file in `records/` into the binary, so a `rocklab` copied to a
//! cluster node still knows the shipped records. Dropping a new file into `records/` and
//! rebuilding embeds it too: no code change.

use std::fmt::Write as _;
use std::path::Path;

/// File kinds the record reader understands, plus the index.
fn is_record_file(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower == "index.ron"
        || [".at2", ".txt", ".csv", ".dat", ".acc"]
            .iter()
            .any(|ext| lower.ends_with(ext))
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("records");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .filter(|e| e.path().is_file())
                .filter_map(|e| e.file_name().into_string().ok())
                .filter(|n| is_record_file(n))
                .collect()
        })
        .unwrap_or_default();
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

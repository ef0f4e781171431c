//! The record library: names → parsed, shared series. Each record is parsed once per process
//! and shared (`Arc`) by every scene that uses it, so a sweep of thousands of scenes reads a
//! file once.
//!
//! A name resolves, in order, to: the index entry's file in the records directory (source
//! `file`), the same file embedded in the binary at build time (`embedded`), the entry's
//! Mavroeidis–Papageorgiou stand-in (`stand-in`). Names not in the index match data files by
//! stem; anything else is read as a path. The records directory is `--records-dir`, else
//! `$ROCKLAB_RECORDS`, else `./records` when it holds an `index.ron`.

use super::pulse::Pulse;
use super::reader::{self, ParseError};
use super::record::Series;
use super::suite::{self, Set, SuiteRecord, SuiteSelect};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

mod embedded {
    include!(concat!(env!("OUT_DIR"), "/embedded_records.rs"));
}

/// Environment variable naming the records directory.
pub const RECORDS_ENV: &str = "ROCKLAB_RECORDS";

/// One entry of `records/index.ron`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordMeta {
    pub name: String,
    /// Row of the paper's Table 1, if the record is one of its five.
    #[serde(default)]
    pub table1: Option<u32>,
    pub event: String,
    pub year: u32,
    pub station: String,
    pub component: String,
    #[serde(default)]
    pub nga: Option<u32>,
    pub mw: f64,
    /// Pulse period Tp (s), Table 1.
    #[serde(default)]
    pub tp: Option<f64>,
    /// PGV (m/s) as printed in Table 1.
    #[serde(default)]
    pub pgv_table1: Option<f64>,
    /// Data file (in the records directory or embedded).
    pub file: String,
    #[serde(default)]
    pub npts: Option<usize>,
    #[serde(default)]
    pub dt: Option<f64>,
    #[serde(default)]
    pub pga_g: Option<f64>,
    #[serde(default)]
    pub pgv: Option<f64>,
    pub units: String,
    pub source: String,
    #[serde(default)]
    pub stand_in: Option<StandIn>,
}

/// A Mavroeidis–Papageorgiou pulse standing in for a record that is not available, fitted to
/// its pulse period and PGV (γ and ν are nominal, not fitted).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StandIn {
    pub tp: f64,
    pub pgv: f64,
    pub gamma: f64,
    pub nu: f64,
    /// Sampling step of the synthesised series (s).
    pub dt: f64,
}

impl StandIn {
    /// Reject parameters that cannot make a pulse (index.ron is hand-edited).
    fn checked(self, name: &str) -> Result<Self, RecordError> {
        let ok = self.tp > 0.0
            && self.pgv > 0.0
            && self.gamma > 1.0
            && self.nu.is_finite()
            && self.dt > 0.0
            && self.dt <= self.tp / 10.0;
        if ok && self.tp.is_finite() && self.pgv.is_finite() {
            Ok(self)
        } else {
            Err(RecordError::Parse(ParseError {
                origin: "index.ron".into(),
                line: 0,
                message: format!(
                    "record '{name}': stand-in needs tp > 0, pgv > 0, γ > 1, finite ν and 0 < dt ≤ tp/10 (got tp: {}, pgv: {}, gamma: {}, nu: {}, dt: {})",
                    self.tp, self.pgv, self.gamma, self.nu, self.dt
                ),
            }))
        }
    }

    /// The pulse sampled at dt, scaled so the sampled history's exact PGV equals `pgv`.
    pub fn series(&self) -> Series {
        let pulse = Pulse::mavroeidis_papageorgiou(self.tp, self.pgv, self.gamma, self.nu);
        let n = (pulse.end() / self.dt).round() as usize + 1;
        let raw = Series::new(
            0.0,
            self.dt,
            (0..n).map(|k| pulse.accel(k as f64 * self.dt)).collect(),
        );
        let k = self.pgv / raw.pgv();
        Series::new(0.0, self.dt, raw.samples().iter().map(|a| a * k).collect())
    }
}

/// Where a record's samples came from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    File(PathBuf),
    Embedded(String),
    StandIn(StandIn),
}

/// What every output says of a stand-in record (results, summary, compare, simulate).
pub const STAND_IN_NOTE: &str = "stand-in records (not the real ground motions: \
Mavroeidis–Papageorgiou pulses fitted to Table 1's Tp and PGV, records/README.md)";

impl Source {
    pub fn label(&self) -> String {
        match self {
            Source::File(p) => format!("file {}", p.display()),
            Source::Embedded(name) => format!("embedded {name}"),
            Source::StandIn(s) => format!(
                "stand-in: MP pulse Tp {} s, PGV {} m/s, γ {}, ν {}",
                s.tp, s.pgv, s.gamma, s.nu
            ),
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Source::File(_) => "file",
            Source::Embedded(_) => "embedded",
            Source::StandIn(_) => "stand-in",
        }
    }
}

/// A loaded record.
#[derive(Debug)]
pub struct Record {
    pub name: String,
    pub meta: Option<RecordMeta>,
    pub source: Source,
    pub series: Arc<Series>,
    /// [`Series::fingerprint`] of `series`, computed once at load.
    pub fingerprint: String,
}

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RecordError {
    #[error(transparent)]
    Parse(#[from] ParseError),
    #[error("{path}: {message}")]
    Io { path: String, message: String },
    #[error(
        "unknown record '{name}'; known records: {known}, and the suite components `<suite>/<id><a|b>` (`rocklab records --suite far_field`) (or give a path to an AT2, one- or two-column file)"
    )]
    Unknown { name: String, known: String },
    #[error(
        "record '{name}': its file {file} is neither in {dir} nor embedded in this binary, and it has no stand-in"
    )]
    Missing {
        name: String,
        file: String,
        dir: String,
    },
    #[error("record suite: {0}")]
    Suite(String),
}

fn is_data_file(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    [".at2", ".txt", ".csv", ".dat", ".acc"]
        .iter()
        .any(|ext| lower.ends_with(ext))
}

fn stem(file: &str) -> &str {
    Path::new(file)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(file)
}

/// A records directory (optional) plus the embedded files, with a parse cache.
pub struct Library {
    dir: Option<PathBuf>,
    index: Vec<RecordMeta>,
    /// Every component of the FEMA P695 sets, in index order (see [`suite`]).
    suites: Vec<SuiteRecord>,
    cache: Mutex<HashMap<(String, bool), Arc<Record>>>,
}

impl Library {
    /// Open a library over `dir` (its `index.ron` if present, else the embedded index).
    pub fn open(dir: Option<PathBuf>) -> Result<Library, RecordError> {
        let dir_index = dir
            .as_ref()
            .map(|d| d.join("index.ron"))
            .filter(|p| p.is_file());
        let (text, origin) = match &dir_index {
            Some(path) => (
                std::fs::read_to_string(path).map_err(|e| RecordError::Io {
                    path: path.display().to_string(),
                    message: e.to_string(),
                })?,
                path.display().to_string(),
            ),
            None => (
                embedded_file("index.ron").unwrap_or("[]").to_string(),
                "embedded index.ron".to_string(),
            ),
        };
        let index: Vec<RecordMeta> = ron::from_str(&text).map_err(|e| {
            RecordError::Parse(ParseError {
                origin: origin.clone(),
                line: e.span.start.line,
                message: format!("{}", e.code),
            })
        })?;
        check_index(&index, &text, &origin)?;
        let suites = read_suites(dir.as_deref())?;
        Ok(Library {
            dir,
            index,
            suites,
            cache: Mutex::new(HashMap::new()),
        })
    }

    /// Every component of the shipped record suites (FEMA P695 sets), in index order.
    pub fn suite_records(&self) -> &[SuiteRecord] {
        &self.suites
    }

    /// The record names a suite selection stands for, in index order.
    pub fn suite(&self, select: &SuiteSelect) -> Result<Vec<String>, RecordError> {
        let table1: Vec<String> = self
            .index
            .iter()
            .filter(|m| m.table1.is_some())
            .map(|m| m.name.clone())
            .collect();
        suite::select(select, &self.suites, &table1).map_err(RecordError::Suite)
    }

    /// The suite component named `name` (`far_field/7a`), if any.
    pub fn suite_entry(&self, name: &str) -> Option<&SuiteRecord> {
        self.suites
            .iter()
            .find(|r| r.id().eq_ignore_ascii_case(name))
    }

    /// The directory named by `$ROCKLAB_RECORDS`, else `./records` if it holds an
    /// `index.ron` (so an unrelated `records/` folder of results is not mistaken for one).
    pub fn default_dir() -> Option<PathBuf> {
        std::env::var_os(RECORDS_ENV)
            .map(PathBuf::from)
            .or_else(|| Some(PathBuf::from("records")).filter(|p| p.join("index.ron").is_file()))
    }

    /// [`Library::default_dir`], refusing a `$ROCKLAB_RECORDS` that is not a directory (as
    /// `--records-dir` is refused): a mistyped variable must not silently fall back.
    pub fn checked_default_dir() -> Result<Option<PathBuf>, RecordError> {
        if let Some(dir) = std::env::var_os(RECORDS_ENV) {
            let dir = PathBuf::from(dir);
            if !dir.is_dir() {
                return Err(RecordError::Io {
                    path: dir.display().to_string(),
                    message: format!(
                        "${RECORDS_ENV} names no directory (hint: point it at a folder of \
                         record files with an index.ron, or unset it)"
                    ),
                });
            }
        }
        Ok(Self::default_dir())
    }

    pub fn dir(&self) -> Option<&Path> {
        self.dir.as_deref()
    }

    pub fn index(&self) -> &[RecordMeta] {
        &self.index
    }

    /// Every record name: index entries first, then data files in the directory or embedded
    /// that no entry claims (named by file stem).
    pub fn names(&self) -> Vec<String> {
        let mut names: Vec<String> = self.index.iter().map(|m| m.name.clone()).collect();
        let claimed = |file: &str| self.index.iter().any(|m| m.file.eq_ignore_ascii_case(file));
        let mut extra: Vec<String> = self
            .dir_files()
            .into_iter()
            .chain(top_level_embedded())
            .filter(|f| is_data_file(f) && !claimed(f))
            .map(|f| stem(&f).to_string())
            .collect();
        extra.sort();
        extra.dedup();
        names.extend(extra);
        names
    }

    fn dir_files(&self) -> Vec<String> {
        let Some(dir) = &self.dir else {
            return Vec::new();
        };
        std::fs::read_dir(dir)
            .map(|entries| {
                entries
                    .filter_map(Result::ok)
                    .filter(|e| e.path().is_file())
                    .filter_map(|e| e.file_name().into_string().ok())
                    .collect()
            })
            .unwrap_or_default()
    }

    fn find_entry(&self, name: &str) -> Option<&RecordMeta> {
        self.index.iter().find(|m| {
            m.name.eq_ignore_ascii_case(name)
                || m.table1.is_some_and(|n| n.to_string() == name)
                || m.file.eq_ignore_ascii_case(name)
                || stem(&m.file).eq_ignore_ascii_case(name)
        })
    }

    /// Load (or fetch from the cache) a record by name, Table 1 number, file stem or path.
    /// `baseline` applies [`Series::baseline_corrected`].
    pub fn load(&self, name: &str, baseline: bool) -> Result<Arc<Record>, RecordError> {
        // Keyed by what the name resolves to, so "northridge" and "2" share one parse; the lock
        // is held while parsing so that concurrent scenes parse a record only once.
        let key = (self.canonical(name), baseline);
        let mut cache = self.cache.lock().expect("cache lock");
        if let Some(hit) = cache.get(&key) {
            return Ok(hit.clone());
        }
        let mut record = self.resolve(name)?;
        if baseline {
            record.series = Arc::new(record.series.baseline_corrected());
        }
        record.fingerprint = record.series.fingerprint();
        let record = Arc::new(record);
        cache.insert(key, record.clone());
        Ok(record)
    }

    /// The index entry's name, else the name as given (a stem or a path).
    fn canonical(&self, name: &str) -> String {
        if let Some(r) = self.suite_entry(name) {
            return format!("suite:{}", r.id());
        }
        self.find_entry(name)
            .map_or_else(|| name.to_string(), |m| format!("index:{}", m.name))
    }

    fn resolve(&self, name: &str) -> Result<Record, RecordError> {
        let dir_label = self
            .dir
            .as_ref()
            .map_or("(no records directory)".to_string(), |d| {
                d.display().to_string()
            });
        if let Some(meta) = self.find_entry(name) {
            let expected = reader::Expected {
                dt: meta.dt,
                units: Some(
                    reader::Units::from_word(&meta.units)
                        .map_err(|why| index_error(&meta.name, why))?,
                ),
                npts: meta.npts,
            };
            let (source, series) = match self.read_data(&meta.file, &expected)? {
                Some(found) => found,
                None => match meta.stand_in {
                    Some(s) => (Source::StandIn(s), s.checked(&meta.name)?.series()),
                    None => {
                        return Err(RecordError::Missing {
                            name: meta.name.clone(),
                            file: meta.file.clone(),
                            dir: dir_label,
                        });
                    }
                },
            };
            return Ok(Record {
                name: meta.name.clone(),
                meta: Some(meta.clone()),
                source,
                series: Arc::new(series),
                fingerprint: String::new(),
            });
        }
        if let Some(entry) = self.suite_entry(name) {
            let (source, series) = self
                .read_data(
                    &entry.path(),
                    &reader::Expected {
                        dt: Some(entry.row.dt),
                        units: None,
                        npts: Some(entry.row.npts),
                    },
                )?
                .ok_or_else(|| RecordError::Missing {
                    name: entry.id(),
                    file: entry.path(),
                    dir: dir_label.clone(),
                })?;
            return Ok(Record {
                name: entry.id(),
                meta: None,
                source,
                series: Arc::new(series),
                fingerprint: String::new(),
            });
        }
        let by_stem = self
            .dir_files()
            .into_iter()
            .chain(top_level_embedded())
            .find(|f| is_data_file(f) && stem(f).eq_ignore_ascii_case(name));
        if let Some(file) = by_stem
            && let Some((source, series)) = self.read_data(&file, &reader::Expected::default())?
        {
            return Ok(Record {
                name: stem(&file).to_string(),
                meta: None,
                source,
                series: Arc::new(series),
                fingerprint: String::new(),
            });
        }
        let path = Path::new(name);
        if path.is_file() {
            let series = read_path(path, None)?;
            return Ok(Record {
                name: name.to_string(),
                meta: None,
                source: Source::File(path.to_path_buf()),
                series: Arc::new(series),
                fingerprint: String::new(),
            });
        }
        Err(RecordError::Unknown {
            name: name.to_string(),
            known: self.names().join(", "),
        })
    }

    /// The file from the directory if there, else from the embedded set; None if neither.
    fn read_data(
        &self,
        file: &str,
        expected: &reader::Expected,
    ) -> Result<Option<(Source, Series)>, RecordError> {
        if let Some(dir) = &self.dir {
            let path = dir.join(file);
            if path.is_file() {
                let text = std::fs::read_to_string(&path).map_err(|e| RecordError::Io {
                    path: path.display().to_string(),
                    message: e.to_string(),
                })?;
                let series = reader::parse_expecting(&text, &path.display().to_string(), expected)?;
                return Ok(Some((Source::File(path.clone()), series)));
            }
        }
        match embedded_file(file) {
            Some(text) => Ok(Some((
                Source::Embedded(file.to_string()),
                reader::parse_expecting(text, &format!("embedded {file}"), expected)?,
            ))),
            None => Ok(None),
        }
    }
}

/// Embedded files at the top of `records/` (sub-folders hold the suites).
fn top_level_embedded() -> impl Iterator<Item = String> {
    embedded::EMBEDDED
        .iter()
        .filter(|(n, _)| !n.contains('/'))
        .map(|(n, _)| n.to_string())
}

/// Each set's `index.csv`, from the records directory if it has one, else embedded.
fn read_suites(dir: Option<&Path>) -> Result<Vec<SuiteRecord>, RecordError> {
    let mut out = Vec::new();
    for set in Set::ALL {
        let file = format!("{}/index.csv", set.dir());
        let on_disk = dir.map(|d| d.join(&file)).filter(|p| p.is_file());
        let (text, origin) = match on_disk {
            Some(path) => (
                std::fs::read_to_string(&path).map_err(|e| RecordError::Io {
                    path: path.display().to_string(),
                    message: e.to_string(),
                })?,
                path.display().to_string(),
            ),
            None => match embedded_file(&file) {
                Some(text) => (text.to_string(), format!("embedded {file}")),
                None => continue,
            },
        };
        out.extend(suite::parse_index(set, &text).map_err(|(line, message)| {
            RecordError::Parse(ParseError {
                origin: origin.clone(),
                line,
                message,
            })
        })?);
    }
    Ok(out)
}

fn index_error(name: &str, message: String) -> RecordError {
    RecordError::Parse(ParseError {
        origin: "index.ron".into(),
        line: 0,
        message: format!("record '{name}': {message}"),
    })
}

/// The strict reading of a records index: no name (or Table 1 row) given to two entries,
/// since a name must pick one file; and units an acceleration has. Errors name the line.
fn check_index(index: &[RecordMeta], text: &str, origin: &str) -> Result<(), RecordError> {
    // Line of each entry's key (from the text's tree; 0 where the text cannot say).
    let tree = crate::ron_syntax::parse(text, false).ok();
    let line_of = |entry: usize, key: &str| {
        tree.as_ref()
            .and_then(|t| t.root.items().get(entry))
            .and_then(|item| item.value.items().iter().find(|i| i.key() == Some(key)))
            .map_or(0, |i| i.value.span().line)
    };
    let error = |entry: usize, key: &str, message: String| {
        RecordError::Parse(ParseError {
            origin: origin.to_string(),
            line: line_of(entry, key),
            message,
        })
    };
    for (i, meta) in index.iter().enumerate() {
        if let Some(first) = index[..i]
            .iter()
            .position(|m| m.name.eq_ignore_ascii_case(&meta.name))
        {
            return Err(error(
                i,
                "name",
                format!(
                    "name: \"{}\" is given to two entries (the first on line {}); a name \
                     must pick one record: rename one",
                    meta.name,
                    line_of(first, "name")
                ),
            ));
        }
        if let Some(row) = meta.table1
            && let Some(first) = index[..i].iter().position(|m| m.table1 == Some(row))
        {
            return Err(error(
                i,
                "table1",
                format!(
                    "table1: {row} is given to '{}' and to '{}' (line {}); a Table 1 row \
                     names one record",
                    meta.name,
                    index[first].name,
                    line_of(first, "table1")
                ),
            ));
        }
        if let Err(why) = reader::Units::from_word(&meta.units) {
            return Err(error(i, "units", format!("record '{}': {why}", meta.name)));
        }
        // Confined to the records folder: an index is data, and must not make rocklab read
        // (and quote in its errors) a file elsewhere (`/etc/…`, `../…`).
        let inside = Path::new(&meta.file)
            .components()
            .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
        if !inside || meta.file.is_empty() {
            return Err(error(
                i,
                "file",
                format!(
                    "record '{}': file: \"{}\" is not a file of the records folder; give its \
                     name relative to the folder (no leading `/`, no `..`), e.g. \
                     \"RSN879_LANDERS_LCN239_FN.txt\"",
                    meta.name,
                    reader::excerpt(&meta.file)
                ),
            ));
        }
    }
    Ok(())
}

fn embedded_file(name: &str) -> Option<&'static str> {
    embedded::EMBEDDED
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|(_, text)| *text)
}

/// Read and parse one file.
pub fn read_path(path: &Path, dt: Option<f64>) -> Result<Series, RecordError> {
    let text = std::fs::read_to_string(path).map_err(|e| RecordError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(reader::parse(&text, &path.display().to_string(), dt)?)
}

static DIR_OVERRIDE: OnceLock<PathBuf> = OnceLock::new();
static GLOBAL: OnceLock<Result<Library, RecordError>> = OnceLock::new();

/// Use `dir` as the records directory of the command line's library. Must be called before the
/// first [`global`] call (the CLI does it while parsing flags); returns false if too late.
pub fn set_records_dir(dir: PathBuf) -> bool {
    DIR_OVERRIDE.set(dir).is_ok() && GLOBAL.get().is_none()
}

/// The command line's library: the records directory of `--records-dir`, else
/// [`Library::default_dir`], opened once per process. Only the entry points (CLI commands,
/// the TUI) and study checks call it; simulations and sweeps take the library they resolve
/// records in as an argument, so a scene depends on no hidden state.
pub fn global() -> Result<&'static Library, RecordError> {
    GLOBAL
        .get_or_init(|| match DIR_OVERRIDE.get() {
            Some(dir) => Library::open(Some(dir.clone())),
            None => Library::open(Library::checked_default_dir()?),
        })
        .as_ref()
        .map_err(Clone::clone)
}

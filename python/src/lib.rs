//! `rocklab._native`: the compiled half of the Python package. Each function runs the same
//! library code as the CLI command it is named after (flags parsed by the CLI's own clap
//! definitions), and hands back text (JSON, CSV, RON) that the pure-Python half turns into
//! dicts and DataFrames. Errors in a study or a flag raise `rocklab.StudyError` with the
//! CLI's message.

mod run;

use clap::Parser;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rocklab::cli::{Cli, Command, UsageError};
use std::path::{Path, PathBuf};

// Named `rocklab.StudyError` (its home in the package) in tracebacks.
create_exception!(
    rocklab,
    StudyError,
    PyValueError,
    "A study, a flag or a value rocklab refuses; the message is the CLI's (file, line, field, hint)."
);

/// A library error as Python sees it: a bad study or flag is a `StudyError` (a ValueError),
/// anything else (a file that cannot be written, a record that cannot be read) a RuntimeError.
/// The message is what the CLI prints after `error: `.
pub(crate) fn to_py(e: anyhow::Error) -> PyErr {
    let message = format!("{e:#}");
    let bad_input = e.downcast_ref::<UsageError>().is_some()
        || e.downcast_ref::<rocklab::study::StudyError>().is_some()
        || e.downcast_ref::<rocklab::risk::RiskError>().is_some();
    if bad_input {
        StudyError::new_err(message)
    } else {
        PyRuntimeError::new_err(message)
    }
}

/// The command line `rocklab <command> <args…>` parsed by the CLI's own definitions: the
/// same flags, defaults and refusals. A refusal is a StudyError with clap's message.
fn parse(command: &str, args: Vec<String>) -> PyResult<Command> {
    let argv = ["rocklab", command]
        .into_iter()
        .map(String::from)
        .chain(args);
    match Cli::try_parse_from(argv) {
        Ok(Cli {
            command: Some(c), ..
        }) => Ok(c),
        Ok(_) => Err(StudyError::new_err(format!("no command `{command}`"))),
        Err(e) => {
            let text = e.render().to_string();
            let text = text.trim().trim_start_matches("error: ");
            Err(StudyError::new_err(text.to_string()))
        }
    }
}

/// `rocklab simulate ARGS --json`: the JSON text it prints and, with `history`, the history
/// as CSV text (the file `--history` writes).
#[pyfunction]
#[pyo3(signature = (args, history=false))]
fn simulate(
    py: Python<'_>,
    mut args: Vec<String>,
    history: bool,
) -> PyResult<(String, Option<String>)> {
    if history {
        // The flags that shape a history (--dt, --max-history-rows) require --history; the
        // history is returned, never written to this name.
        args.extend(["--history".into(), "-".into()]);
    }
    let Command::Simulate(args) = parse("simulate", args)? else {
        unreachable!("parsed as simulate")
    };
    py.allow_threads(|| {
        let run = rocklab::cli::simulate::compute(&args, history)?;
        let json = rocklab::cli::simulate::json_output(&run)?.to_string();
        let csv = match &run.history {
            Some(h) => Some(String::from_utf8(rocklab::report::history_csv(h)?)?),
            None => None,
        };
        Ok((json, csv))
    })
    .map_err(to_py)
}

/// `rocklab records ARGS --json`: the JSON array it prints.
#[pyfunction]
fn records(py: Python<'_>, args: Vec<String>) -> PyResult<String> {
    let Command::Records(args) = parse("records", args)? else {
        unreachable!("parsed as records")
    };
    py.allow_threads(|| Ok(rocklab::cli::records::json(&args)?.to_string()))
        .map_err(to_py)
}

/// `rocklab compare ARGS --json`: the JSON it prints.
/// `rocklab risk ARGS`: computes and writes risk.csv, risk.json (and the figure) beside the
/// results, as the CLI does; Python reads risk.csv back.
#[pyfunction]
fn risk(py: Python<'_>, args: Vec<String>) -> PyResult<()> {
    let Command::Risk(args) = parse("risk", args)? else {
        unreachable!("parsed as risk")
    };
    py.allow_threads(|| rocklab::cli::risk::assess_and_write(&args).map(|_| ()))
        .map_err(to_py)
}

#[pyfunction]
fn compare(py: Python<'_>, args: Vec<String>) -> PyResult<String> {
    let Command::Compare(args) = parse("compare", args)? else {
        unreachable!("parsed as compare")
    };
    py.allow_threads(|| Ok(rocklab::cli::compare::json(&args)?.to_string()))
        .map_err(to_py)
}

/// `rocklab table RESULTS [--wide]`: the CSV text it prints.
#[pyfunction]
#[pyo3(signature = (results, wide=false))]
fn table(py: Python<'_>, results: PathBuf, wide: bool) -> PyResult<String> {
    py.allow_threads(|| {
        let path = rocklab::cli::compare::resolve_results(&results);
        let results = rocklab::report::load_results(&path)?;
        let layout = if wide {
            rocklab::report::CsvLayout::Wide
        } else {
            rocklab::report::CsvLayout::Long
        };
        Ok(String::from_utf8(rocklab::report::results_csv_layout(
            &results, layout,
        )?)?)
    })
    .map_err(to_py)
}

/// A study from a file (`is_text` false; `default` is the built-in study, as for `rocklab
/// run`) or from RON text: its canonical JSON (serde's form of the study) and the RON text
/// it came from.
#[pyfunction]
#[pyo3(signature = (source, is_text=false))]
fn study_parse(source: &str, is_text: bool) -> PyResult<(String, String)> {
    let (study, text) = load_study(source, is_text).map_err(to_py)?;
    let json = serde_json::to_string(&study).map_err(|e| to_py(e.into()))?;
    Ok((json, text))
}

/// The RON text of the study whose JSON form is `json`, keeping the comments, spelling and
/// left-out defaults of `original` where the study still agrees with it. Refused (with the
/// field named) if the study is not valid.
#[pyfunction]
#[pyo3(signature = (json, original=None))]
fn study_ron(json: &str, original: Option<&str>) -> PyResult<String> {
    let study: rocklab::study::Study =
        serde_json::from_str(json).map_err(|e| StudyError::new_err(format!("study: {e}")))?;
    let text = study.to_ron_keeping(original).text;
    // What is written must load back as the same study: run it through the parser.
    let again = rocklab::study::Study::from_ron_str(&text, "<study>")
        .map_err(|e| StudyError::new_err(e.to_string()))?;
    if again != study {
        return Err(PyRuntimeError::new_err(
            "the study's RON text does not read back as the same study (please report)",
        ));
    }
    Ok(text)
}

/// A study and the RON text it was read from.
pub(crate) fn load_study(
    source: &str,
    is_text: bool,
) -> anyhow::Result<(rocklab::study::Study, String)> {
    use rocklab::study::Study;
    if is_text {
        return Ok((
            Study::from_ron_str(source, "<study text>")?,
            source.to_string(),
        ));
    }
    if source == "default" && !Path::new(source).exists() {
        let study = Study::builtin_default();
        let text = study.to_ron_keeping(None).text;
        return Ok((study, text));
    }
    let study = rocklab::cli::run::load_study(source)?;
    let text = std::fs::read_to_string(source)?;
    Ok((study, text))
}

/// The wide table's coordinate columns, one per study axis, of the results at `results`.
#[pyfunction]
fn axis_columns(py: Python<'_>, results: PathBuf) -> PyResult<Vec<String>> {
    py.allow_threads(|| {
        let path = rocklab::cli::compare::resolve_results(&results);
        Ok(rocklab::report::axis_columns(
            &rocklab::report::load_results(&path)?,
        ))
    })
    .map_err(to_py)
}

/// The file names of the tables a run writes beside its results, by table.
#[pyfunction]
fn table_files() -> Vec<(&'static str, &'static str)> {
    rocklab::report::TABLE_FILES.to_vec()
}

/// The response quantities' names (the results CSV's `quantity` values), in table order.
#[pyfunction]
fn quantities() -> Vec<&'static str> {
    rocklab::sim::Quantity::ALL
        .iter()
        .map(|q| q.info().name)
        .collect()
}

/// Each response quantity's unit (the quantity table's spelling), by name.
#[pyfunction]
fn quantity_units() -> Vec<(&'static str, &'static str)> {
    rocklab::sim::Quantity::ALL
        .iter()
        .map(|q| (q.info().name, q.info().unit))
        .collect()
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("StudyError", m.py().get_type::<StudyError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(records, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(risk, m)?)?;
    m.add_function(wrap_pyfunction!(table, m)?)?;
    m.add_function(wrap_pyfunction!(study_parse, m)?)?;
    m.add_function(wrap_pyfunction!(study_ron, m)?)?;
    m.add_function(wrap_pyfunction!(table_files, m)?)?;
    m.add_function(wrap_pyfunction!(axis_columns, m)?)?;
    m.add_function(wrap_pyfunction!(quantities, m)?)?;
    m.add_function(wrap_pyfunction!(quantity_units, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    Ok(())
}

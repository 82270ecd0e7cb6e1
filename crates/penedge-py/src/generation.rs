//! `generate`: a generation spec (a file, TOML text or a dict) to a block system and its
//! report (core `generation` and `io::spec`).

use crate::arrays;
use crate::errors::{to_py_err, Error};
use crate::system::BlockSystem;
use penedge::generation::{
    generate_with, Generated, GenerationError, Limits, Problem, Progress, Spec, SpecError,
};
use penedge::io::spec::{parse_toml, read_spec};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyMapping, PyString, PyTuple};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The shortest time between two calls of the progress callback.
const PROGRESS_INTERVAL: Duration = Duration::from_millis(100);

/// Cuts a rock domain into convex blocks by the joints of a spec (see ``docs/generation.md``).
///
/// The work is done in Rust without the GIL: planes expanded from the joint sets descend a
/// cutting tree; finite joints split only the blocks they cross completely; slivers are
/// kept or dropped, and counted either way.
///
/// Parameters
/// ----------
/// spec : str, os.PathLike or dict
///     A spec file (TOML, or JSON when the name ends in ``.json``); a str holding a newline,
///     or an ``=`` and a ``{`` and naming no file (``"domain = {...}"``), is TOML text; a dict is the spec's structure (``{"domain": {...}, "joints": [...],
///     "options": {...}}``; lists, numpy arrays, numbers and strings; a None value counts as
///     missing).
/// progress : callable, optional
///     Called as ``progress(planes_done, planes_total, blocks)`` at most ten times a second
///     and once at the end, while the joints cut and while the excavations do (then with
///     every plane done, and ``blocks`` the convex parts held so far). If it raises, the run
///     stops there (between two planes' cuts, or two of an excavation's) and its exception
///     is raised, with a note of how far the run got. Ctrl-C (``KeyboardInterrupt``) stops
///     the run the same way, with or without a callback.
/// max_blocks : int, optional
///     The most blocks the run may make. Before cutting, the blocks are estimated from the
///     arrangement of the planes (``1 + planes + lines + points`` where they meet: the
///     product of the plane counts for joint sets that fill the domain); a spec estimated to
///     make more is refused, and a run that makes more stops (an excavation too, once it holds
///     more convex parts). Default: what half the memory
///     available holds (about 4 kB a block); give a larger number where the estimate is
///     too high. At most 2**63 - 1 (the command line's cap for no limit).
///
/// Returns
/// -------
/// system : BlockSystem
///     The blocks, with the domain, joint table and face origins.
/// report : dict
///     ``blocks``, ``joint_planes``, ``splits``, ``partial_cuts_skipped`` (finite joints that
///     end inside a block, which is left whole), ``partial_cuts_by_entry``, ``bridged_cuts``
///     (finite joints with rock bridges that end inside a block, which is cut through),
///     ``set_planes_outside``, ``retried_cuts``, ``domain_volume``, ``block_volume``,
///     ``volume_error``, ``slivers`` (``policy``, ``min_volume``, ``min_thickness``,
///     ``count``, ``volume``, ``kept_ids``) and ``tiny`` (blocks below 1e-3 of the median
///     block volume, slivers or not: ``median_volume``, ``threshold``, ``count``,
///     ``smallest``; of the blocks the joints cut, before any excavation) and
///     ``excavation_slivers`` (the blocks the excavations leave that are slivers, by body,
///     with the same limits and policy: ``count``, ``volume``, ``kept_bodies``, body ids in
///     the system returned; docs/generation.md, "Slivers").
///
/// Raises
/// ------
/// InputError
///     ``max_blocks`` below 1 or above 2**63 - 1 (kind ``out_of_range``).
/// SpecError
///     A bad field: ``field`` names it (``joints[0].dip``), ``kind`` says what is wrong;
///     ``kind == "too_many_blocks"`` (``field == "joints"``): more blocks than
///     ``max_blocks``, estimated before cutting or made by the run; the message gives the
///     estimate and how to proceed.
/// BlockError
///     A joint cannot cut a block consistently (the message names the joint).
/// OSError
///     The spec file cannot be read.
///
/// Examples
/// --------
/// >>> import penedge
/// >>> system, report = penedge.generate({
/// ...     "domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
/// ...     "joints": [{"type": "set", "dip": 0, "dip_direction": 0, "spacing": 2.5}],
/// ... })
/// >>> len(system), report["joint_planes"], report["volume_error"] < 1e-12
/// (4, 3, True)
/// >>> try:
/// ...     penedge.generate({"domain": {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]},
/// ...                       "joints": [{"type": "plane", "point": [0, 0, 0.5],
/// ...                                   "dip": 120, "dip_direction": 0}]})
/// ... except penedge.SpecError as e:
/// ...     print(e.field, "-", e)
/// joints[0].dip - joints[0].dip: dip must be between 0 and 90 degrees, got 120
#[pyfunction]
#[pyo3(signature = (spec, progress = None, max_blocks = None))]
pub fn generate<'py>(
    py: Python<'py>,
    spec: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
    max_blocks: Option<arrays::Count>,
) -> PyResult<(BlockSystem, Bound<'py, PyAny>)> {
    let limits = match arrays::Count::optional(max_blocks, "max_blocks")? {
        None => Limits::from_memory(),
        Some(n) => Limits::blocks(block_limit(&n)?),
    };
    let (spec, file) = read(py, spec)?;
    let in_file = |e: Error| match &file {
        Some(path) => e.in_file(path),
        None => e,
    };
    let Generated { system, report } = run(py, &spec, &limits, progress).map_err(|e| match e {
        Failure::Generation(e) => to_py_err(in_file(e.into())),
        Failure::Progress(e) => e,
    })?;
    Ok((BlockSystem::wrap(system), arrays::to_python(py, &report)?))
}

/// The largest `max_blocks`: the command line's cap (`--max-blocks`), where a larger limit
/// is no limit.
const MAX_BLOCK_LIMIT: i64 = i64::MAX;

/// `max_blocks` checked: a whole number from 1 to [`MAX_BLOCK_LIMIT`], else an `InputError`
/// naming it and the range.
fn block_limit(n: &arrays::Whole) -> PyResult<u64> {
    match n.value() {
        Some(n) if n >= 1 => Ok(n as u64),
        _ => {
            let message = format!(
                "max_blocks must be a whole number from 1 to 2**63 - 1 ({MAX_BLOCK_LIMIT}), \
                 got {n}"
            );
            Err(crate::errors::input_error("out_of_range", message))
        }
    }
}

/// The spec, parsed (its values are checked by the core as it runs), and its file.
fn read(py: Python<'_>, spec: &Bound<'_, PyAny>) -> PyResult<(Spec, Option<PathBuf>)> {
    if let Ok(text) = spec.cast::<PyString>() {
        let text = text.to_str()?;
        // TOML text: it holds a newline, or it is one line with an inline table (a spec on
        // one line has one: `domain = { ... }`) and names no file. A mistyped file name
        // (`runs/dip=30.tom`) stays a missing file, not a TOML syntax error.
        let one_line = text.contains('=') && text.contains('{') && !Path::new(text).exists();
        if text.contains('\n') || one_line {
            return Ok((parse_toml(text).map_err(to_py_err)?, None));
        }
    }
    if spec.is_instance_of::<PyDict>() || spec.is_instance_of::<PyMapping>() {
        let text = toml_text(spec, "spec")?;
        let parsed = parse_toml(&text).map_err(|e| to_py_err(in_dict(&text, e, "")))?;
        return Ok((parsed, None));
    }
    let path: PathBuf = spec.extract().map_err(|_| {
        let kind = spec.get_type().name().map_or("?".into(), |n| n.to_string());
        crate::errors::input_error(
            "spec",
            format!("spec must be a path, TOML text or a dict, got {kind}"),
        )
    })?;
    let spec = py
        .detach(|| read_spec(&path))
        .map_err(|e| to_py_err(Error::from(e).in_file(&path)))?;
    Ok((spec, Some(path)))
}

/// Why a run stopped: the core's error, or the progress callback's exception.
enum Failure {
    Generation(GenerationError),
    Progress(PyErr),
}

/// Runs the generation without the GIL; now and then (every [`PROGRESS_INTERVAL`]) takes
/// the GIL to run Python's signal handlers (Ctrl-C) and call `progress`, and stops the run
/// there when either raises.
fn run(
    py: Python<'_>,
    spec: &Spec,
    limits: &Limits,
    progress: Option<Py<PyAny>>,
) -> Result<Generated, Failure> {
    let mut failure: Option<PyErr> = None;
    let result = py.detach(|| {
        let mut last = Instant::now();
        let mut report = |p: Progress| {
            let done = p.is_last();
            if !done && last.elapsed() < PROGRESS_INTERVAL {
                return ControlFlow::Continue(());
            }
            last = Instant::now();
            Python::attach(|py| {
                let args = (p.planes_done, p.planes_total, p.blocks);
                let call = py.check_signals().and_then(|()| match &progress {
                    Some(callback) => callback.call1(py, args).map(drop),
                    None => Ok(()),
                });
                match call {
                    Ok(()) => ControlFlow::Continue(()),
                    Err(e) => {
                        failure = Some(e);
                        ControlFlow::Break(())
                    }
                }
            })
        };
        generate_with(spec, limits, &mut report)
    });
    match (failure, result) {
        (
            Some(e),
            Err(GenerationError::Cancelled {
                planes_done,
                planes_total,
            }),
        ) => {
            let note = format!(
                "penedge.generate stopped after {planes_done} of {planes_total} joint planes"
            );
            let _ = e.value(py).call_method1("add_note", (note,));
            Err(Failure::Progress(e))
        }
        (Some(e), _) => Err(Failure::Progress(e)),
        (None, result) => result.map_err(Failure::Generation),
    }
}

/// An error of a spec given as a dict, parsed from the TOML text written of it
/// ([`toml_text`]): the `line L, column C` of a syntax error are of that text, which the
/// caller never saw, so they become the path of the field they point at, under `root` (the
/// dict's own path: empty for a whole spec, `excavation` for one excavation): `joints[1].dip:
/// got the text "steep", expected a number`; an unknown field, and a missing one, named by
/// its table (`joints[0]: unknown field `spasing` ...`). Any other error is left as it is.
pub(crate) fn in_dict(text: &str, e: SpecError, root: &str) -> SpecError {
    let Problem::Syntax(message) = &e.problem else {
        return e;
    };
    let located = message
        .strip_prefix("line ")
        .and_then(|rest| rest.split_once(", column "))
        .and_then(|(line, rest)| Some((line.parse::<usize>().ok()?, rest.split_once(": ")?.1)));
    let Some((line, what)) = located else {
        return e;
    };
    let (table, key, header) = field_at(text, line);
    let unknown = what.starts_with("unknown field");
    let missing = what.starts_with("the field `") && what.ends_with("` is missing");
    // A field missing from the whole spec is placed at its start, which is also the first
    // table's header when the spec has no plain key: a top-level field (in no table) is the
    // spec's.
    let top_level = root.is_empty()
        && ["domain", "joints", "excavations", "options", "unit"]
            .iter()
            .any(|f| what == format!("the field `{f}` is missing"));
    let join = |a: &str, b: &str| match (a.is_empty(), b.is_empty()) {
        (true, _) => b.to_string(),
        (_, true) => a.to_string(),
        _ => format!("{a}.{b}"),
    };
    let path = match key {
        _ if top_level => String::new(),
        // A header's own table, where a field is missing or a value is wrong.
        Some(key) if header && !unknown => join(&table, &key),
        // A plain key's value.
        Some(key) if !unknown && !missing => join(&table, &key),
        _ => table,
    };
    let field = match join(root, &path) {
        f if f.is_empty() => "spec".to_string(),
        f => f,
    };
    SpecError::new(field, Problem::Syntax(what.to_string()))
}

/// Where line `line` (from 1) of TOML text written by `toml::to_string` is: the path of the
/// table it is in (`joints[1]`, `joints[0].extent`; empty for the top level), the key it
/// gives there, if any, and whether the line is a header (`[a.b]` or `[[a.b]]` gives key `b`
/// in table `a`). The writer puts every table under a header, arrays of tables as `[[...]]`,
/// one key per line.
fn field_at(text: &str, line: usize) -> (String, Option<String>, bool) {
    // Per array of tables (its dotted header), the entries seen so far.
    let mut entries: std::collections::HashMap<String, usize> = Default::default();
    let mut table = String::new();
    let unquote = |k: &str| k.trim().trim_matches('"').to_string();
    // The path of a header's dotted name: each array of tables with its last entry.
    let path = |names: &[&str], entries: &std::collections::HashMap<String, usize>| {
        let mut out = String::new();
        for k in 0..names.len() {
            if k > 0 {
                out.push('.');
            }
            out.push_str(&unquote(names[k]));
            if let Some(n) = entries.get(&names[..=k].join(".")) {
                out.push_str(&format!("[{}]", n - 1));
            }
        }
        out
    };
    for (i, row) in text.lines().enumerate().take(line) {
        let row = row.trim();
        let header = row
            .strip_prefix("[[")
            .and_then(|r| r.strip_suffix("]]"))
            .map(|h| (h, true))
            .or_else(|| {
                row.strip_prefix('[')
                    .and_then(|r| r.strip_suffix(']'))
                    .map(|h| (h, false))
            });
        if let Some((name, array)) = header {
            let names: Vec<&str> = name.split('.').map(str::trim).collect();
            if array {
                let dotted = names.join(".");
                let nested = format!("{dotted}.");
                entries.retain(|k, _| !k.starts_with(&nested));
                *entries.entry(dotted).or_insert(0) += 1;
            }
            if i + 1 == line {
                let parent = path(&names[..names.len() - 1], &entries);
                let last = names.len() - 1;
                let mut key = unquote(names[last]);
                if let Some(n) = entries.get(&names.join(".")) {
                    key.push_str(&format!("[{}]", n - 1));
                }
                return (parent, Some(key), true);
            }
            table = path(&names, &entries);
        } else if i + 1 == line {
            let key = row.split_once(" = ").map(|(k, _)| unquote(k));
            return (table, key, false);
        }
    }
    (table, None, false)
}

/// A spec given as a dict (or a part of one: `field` names it, `spec` for a whole spec,
/// `excavation` for one excavation), written as TOML text. Anything but a mapping is an
/// `InputError` (kind `"type"`) naming `field`.
pub(crate) fn toml_text(spec: &Bound<'_, PyAny>, field: &str) -> PyResult<String> {
    let Ok(mapping) = spec.cast::<PyMapping>() else {
        let kind = spec.get_type().name().map_or("?".into(), |n| n.to_string());
        return Err(crate::errors::input_error(
            "type",
            format!("{field} must be a dict (a mapping of its fields), got {kind}"),
        ));
    };
    let table = toml_table(mapping, field, 0)?;
    toml::to_string(&table).map_err(|e| spec_error(field, e.to_string()))
}

fn spec_error(field: &str, message: String) -> PyErr {
    let message = format!("{field}: {message}");
    to_py_err(Error::Spec("invalid".into(), field.into(), message))
}

/// The deepest nesting of lists and tables a spec may have (a spec needs four or five): a
/// list or dict that contains itself, or absurd nesting, is an error, not a stack overflow.
const MAX_NESTING: usize = 32;

/// A Python value as a TOML value (None: left out), `depth` levels down.
fn nested_value(
    obj: &Bound<'_, PyAny>,
    field: &str,
    depth: usize,
) -> PyResult<Option<toml::Value>> {
    use toml::Value;
    if obj.is_none() {
        return Ok(None);
    }
    if depth > MAX_NESTING {
        let msg = format!(
            "nested more than {MAX_NESTING} levels deep (a list or dict that contains itself?)"
        );
        return Err(spec_error(field, msg));
    }
    let value = if obj.is_instance_of::<PyBool>() {
        Value::Boolean(obj.extract()?)
    } else if obj.is_instance_of::<PyInt>() {
        let n: i64 = obj
            .extract()
            .map_err(|_| spec_error(field, format!("the integer {obj} is too large")))?;
        Value::Integer(n)
    } else if obj.is_instance_of::<PyFloat>() {
        Value::Float(obj.extract()?)
    } else if let Ok(s) = obj.cast::<PyString>() {
        Value::String(s.to_str()?.to_string())
    } else if let Ok(mapping) = obj.cast::<PyMapping>() {
        Value::Table(toml_table(mapping, field, depth)?)
    } else if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        Value::Array(toml_array(obj, field, depth)?)
    } else if obj.hasattr("tolist")? {
        // numpy arrays and scalars
        let listed = obj.call_method0("tolist")?;
        if !listed.get_type().is(obj.get_type()) {
            return nested_value(&listed, field, depth + 1);
        }
        // A scalar numpy keeps as it is (`np.longdouble`): a number as its float, if any
        // (it had gone round to the nesting limit, reported as a loop).
        let kind = obj.get_type().name()?;
        let x: f64 = obj
            .call_method0("__float__")
            .and_then(|f| f.extract())
            .map_err(|_| spec_error(field, format!("must be a number, got {kind}")))?;
        Value::Float(x)
    } else {
        let kind = obj.get_type().name()?;
        let msg = format!("must be a number, string, list or table, got {kind}");
        return Err(spec_error(field, msg));
    };
    Ok(Some(value))
}

fn toml_table(mapping: &Bound<'_, PyMapping>, field: &str, depth: usize) -> PyResult<toml::Table> {
    let mut table = toml::Table::new();
    for item in mapping.items()?.iter() {
        let (key, value): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract()?;
        let key = key.str()?.to_string();
        let path = if field == "spec" {
            key.clone()
        } else {
            format!("{field}.{key}")
        };
        if let Some(v) = nested_value(&value, &path, depth + 1)? {
            table.insert(key, v);
        }
    }
    Ok(table)
}

fn toml_array(list: &Bound<'_, PyAny>, field: &str, depth: usize) -> PyResult<Vec<toml::Value>> {
    let mut out = Vec::new();
    for (i, item) in list.try_iter()?.enumerate() {
        let path = format!("{field}[{i}]");
        match nested_value(&item?, &path, depth + 1)? {
            Some(v) => out.push(v),
            None => return Err(spec_error(&path, "None in a list".into())),
        }
    }
    Ok(out)
}

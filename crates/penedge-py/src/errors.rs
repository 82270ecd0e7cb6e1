//! The Python exceptions of penedge and the one conversion from core errors to them.
//!
//! ```text
//! PenedgeError(Exception)                every error raised by penedge
//! ├── InputError(PenedgeError, ValueError)      wrong shape, dtype or value of an argument
//! ├── BlockError(PenedgeError, ValueError)      vertices + faces or half-spaces: not a convex block
//! ├── ToleranceError(PenedgeError, ValueError)  impossible gap / length
//! ├── SpecError(PenedgeError, ValueError)       a generation spec with a bad field (`field`)
//! ├── FileFormatError(PenedgeError, ValueError) a block file that is not valid (`field`)
//! └── MechanicsError(PenedgeError, ValueError)  a simulation that cannot be set up or go on
//! ```
//!
//! Each exception carries `kind`, a snake_case name of what went wrong (`"not_convex"`,
//! `"out_of_range"`, `"shape"`, ...), so callers need not parse messages; `SpecError` and
//! `FileFormatError` also carry `field`, the path of the bad field (`joints[0].dip`), or None.
//! A file that cannot be read or written raises the standard `OSError` subclass
//! (`FileNotFoundError`, `PermissionError`, ...) with its `filename`. The classes are made
//! once per process with `type(name, bases, dict)`, since PyO3's `create_exception!` takes one
//! base only.

use penedge::block::BlockError;
use penedge::generation::{GenerationError, SpecError};
use penedge::io::IoError;
use penedge::mechanics::MechanicsError;
use penedge::system::SystemError;
use penedge::tolerance::ToleranceError;
use pyo3::exceptions::{PyException, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use std::path::{Path, PathBuf};

/// Every error the bindings raise, before conversion to a Python exception: the class, a
/// snake_case `kind` and the message.
#[derive(Debug)]
pub enum Error {
    /// An argument of the wrong shape, dtype or value: `InputError`.
    Input(String, String),
    /// Not a valid convex block: `BlockError`.
    Block(String, String),
    /// An impossible tolerance: `ToleranceError`.
    Tolerance(String, String),
    /// A bad generation spec: `SpecError` (kind, field, message).
    Spec(String, String, String),
    /// A bad block file: `FileFormatError` (kind, field if known, message).
    FileFormat(String, Option<String>, String),
    /// The operating system refused to read or write a file: `OSError`.
    Os(PathBuf, std::io::Error),
    /// A simulation that cannot be set up or go on: `MechanicsError`.
    Mechanics(String, String),
}

impl From<MechanicsError> for Error {
    fn from(e: MechanicsError) -> Self {
        match e {
            MechanicsError::Tolerance(t) => t.into(),
            other => Error::Mechanics(variant_name(&other), other.to_string()),
        }
    }
}

impl From<SpecError> for Error {
    fn from(e: SpecError) -> Self {
        Error::Spec(variant_name(&e.problem), e.field.clone(), e.to_string())
    }
}

impl From<GenerationError> for Error {
    fn from(e: GenerationError) -> Self {
        match e {
            GenerationError::Spec(s) => s.into(),
            GenerationError::Cut { ref source, .. } => {
                Error::Block(variant_name(source), e.to_string())
            }
            GenerationError::TooManyBlocks { .. } | GenerationError::Outgrew { .. } => {
                Error::Spec("too_many_blocks".into(), "joints".into(), e.to_string())
            }
            GenerationError::Cancelled { .. } => Error::Input("cancelled".into(), e.to_string()),
        }
    }
}

impl From<IoError> for Error {
    fn from(e: IoError) -> Self {
        match e {
            IoError::Io { path, source } => Error::Os(path, source),
            IoError::Syntax { .. } => Error::FileFormat("syntax".into(), None, e.to_string()),
            IoError::Format { ref field, .. } => {
                Error::FileFormat("format".into(), Some(field.clone()), e.to_string())
            }
            IoError::Spec(s) => s.into(),
        }
    }
}

impl Error {
    /// The same error with the message prefixed by the file it is about (when the core's
    /// message does not name it already).
    pub fn in_file(self, path: &Path) -> Self {
        let prefix = |m: String| {
            let name = path.display().to_string();
            if m.starts_with(&name) {
                m
            } else {
                format!("{name}: {m}")
            }
        };
        match self {
            Error::Spec(kind, field, m) => Error::Spec(kind, field, prefix(m)),
            Error::FileFormat(kind, field, m) => Error::FileFormat(kind, field, prefix(m)),
            other => other,
        }
    }
}

impl From<BlockError> for Error {
    fn from(e: BlockError) -> Self {
        Error::Block(variant_name(&e), e.to_string())
    }
}

impl From<ToleranceError> for Error {
    fn from(e: ToleranceError) -> Self {
        Error::Tolerance(variant_name(&e), e.to_string())
    }
}

impl From<SystemError> for Error {
    fn from(e: SystemError) -> Self {
        match e {
            SystemError::Block(b) => b.into(),
            SystemError::DegeneratePlane { .. } => {
                Error::Input("degenerate_plane".into(), e.to_string())
            }
            SystemError::Generation(g) => g.into(),
            SystemError::Arrays { .. } => Error::Input("arrays".into(), e.to_string()),
            // The bindings check the lengths first (`arrays::planes`): a wrong shape.
            SystemError::PlaneCount { .. } => Error::Input("shape".into(), e.to_string()),
            SystemError::InvalidBlock { ref source, .. } => {
                Error::Block(variant_name(source), e.to_string())
            }
        }
    }
}

/// An `InputError` with the given kind and message.
pub fn input_error(kind: &str, message: impl Into<String>) -> PyErr {
    to_py_err(Error::Input(kind.into(), message.into()))
}

/// Converts any core error to its Python exception (the one conversion of the bindings).
pub fn to_py_err(err: impl Into<Error>) -> PyErr {
    let err = err.into();
    Python::attach(|py| {
        let classes = match classes(py) {
            Ok(c) => c,
            Err(e) => return e,
        };
        let (class, kind, field, message) = match &err {
            Error::Input(kind, m) => (&classes.input, kind, None, m),
            Error::Block(kind, m) => (&classes.block, kind, None, m),
            Error::Tolerance(kind, m) => (&classes.tolerance, kind, None, m),
            Error::Spec(kind, field, m) => (&classes.spec, kind, Some(field), m),
            Error::FileFormat(kind, field, m) => (&classes.file_format, kind, field.as_ref(), m),
            Error::Mechanics(kind, m) => (&classes.mechanics, kind, None, m),
            Error::Os(path, source) => return os_error(py, path, source).unwrap_or_else(|e| e),
        };
        instantiate(class.bind(py), kind, field, message).unwrap_or_else(|e| e)
    })
}

fn instantiate(
    class: &Bound<'_, PyType>,
    kind: &str,
    field: Option<&String>,
    message: &str,
) -> PyResult<PyErr> {
    let value = class.call1((message,))?;
    value.setattr("kind", kind)?;
    if let Some(field) = field {
        value.setattr("field", field)?;
    }
    Ok(PyErr::from_value(value))
}

/// `OSError(errno, strerror, filename)`, which Python turns into the matching subclass
/// (`FileNotFoundError`, `IsADirectoryError`, ...); `OSError("path: message")` without errno.
fn os_error(py: Python<'_>, path: &Path, source: &std::io::Error) -> PyResult<PyErr> {
    let class = py.get_type::<PyOSError>();
    let value = match source.raw_os_error() {
        Some(errno) => {
            let strerror = py.import("os")?.getattr("strerror")?.call1((errno,))?;
            class.call1((errno, strerror, path.to_string_lossy()))?
        }
        None => class.call1((format!("{}: {source}", path.display()),))?,
    };
    Ok(PyErr::from_value(value))
}

/// `NotConvex { .. }` -> `not_convex`.
fn variant_name(e: &impl std::fmt::Debug) -> String {
    let debug = format!("{e:?}");
    let mut name = String::new();
    for c in debug.chars().take_while(|c| c.is_ascii_alphanumeric()) {
        if c.is_ascii_uppercase() && !name.is_empty() {
            name.push('_');
        }
        name.push(c.to_ascii_lowercase());
    }
    name
}

/// The exception classes, made on first use.
pub struct Classes {
    /// `PenedgeError`.
    pub base: Py<PyType>,
    /// `InputError`.
    pub input: Py<PyType>,
    /// `BlockError`.
    pub block: Py<PyType>,
    /// `ToleranceError`.
    pub tolerance: Py<PyType>,
    /// `SpecError`.
    pub spec: Py<PyType>,
    /// `FileFormatError`.
    pub file_format: Py<PyType>,
    /// `MechanicsError`.
    pub mechanics: Py<PyType>,
}

static CLASSES: PyOnceLock<Classes> = PyOnceLock::new();

/// The exception classes (made once per process).
pub fn classes(py: Python<'_>) -> PyResult<&Classes> {
    CLASSES.get_or_try_init(py, || make_classes(py))
}

fn make_classes(py: Python<'_>) -> PyResult<Classes> {
    let exception = py.get_type::<PyException>().into_any();
    let value_error = py.get_type::<PyValueError>().into_any();
    let base = make_class(
        py,
        "PenedgeError",
        "Base class of every error raised by penedge.",
        &[&exception],
    )?;
    let sub =
        |name: &str, doc: &str| make_class(py, name, doc, &[base.bind(py).as_any(), &value_error]);
    Ok(Classes {
        input: sub(
            "InputError",
            "An argument of the wrong shape, dtype or value.",
        )?,
        block: sub(
            "BlockError",
            "Vertices and faces (or half-spaces) that do not make a valid convex block.",
        )?,
        tolerance: sub(
            "ToleranceError",
            "An impossible tolerance: gap not in [0, 0.01) or above 0 but below 16 * 2**-52, length not in [0, 0.1), length < 10 * gap, a negative absolute_gap, or both gaps.",
        )?,
        spec: sub(
            "SpecError",
            "A generation spec with a bad field: `field` is its path (``joints[0].dip``), \
             `kind` the problem (``dip``, ``not_positive``, ``missing``, ``syntax``, ...).",
        )?,
        file_format: sub(
            "FileFormatError",
            "A block file that is not valid JSON (``kind == 'syntax'``) or has a wrong field \
             (``kind == 'format'``; `field` is its path, ``blocks[3].faces``).",
        )?,
        mechanics: sub(
            "MechanicsError",
            "A simulation that cannot be set up or go on: joint properties, density, damping \
             or time step out of range, no free body, two bodies overlapping deeper than the \
             detection gap (`kind` names it: ``stiffness``, ``friction``, ``time_step``, \
             ``no_free_body``, ``penetration``, ...).",
        )?,
        base,
    })
}

fn make_class(
    py: Python<'_>,
    name: &str,
    doc: &str,
    bases: &[&Bound<'_, PyAny>],
) -> PyResult<Py<PyType>> {
    let dict = PyDict::new(py);
    dict.set_item("__doc__", doc)?;
    dict.set_item("__module__", "penedge")?;
    dict.set_item("kind", "")?;
    dict.set_item("field", py.None())?;
    let bases = PyTuple::new(py, bases)?;
    let class = py.get_type::<PyType>().call1((name, bases, dict))?;
    Ok(class.cast_into::<PyType>()?.unbind())
}

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let c = classes(m.py())?;
    m.add("PenedgeError", c.base.clone_ref(m.py()))?;
    m.add("InputError", c.input.clone_ref(m.py()))?;
    m.add("BlockError", c.block.clone_ref(m.py()))?;
    m.add("ToleranceError", c.tolerance.clone_ref(m.py()))?;
    m.add("SpecError", c.spec.clone_ref(m.py()))?;
    m.add("FileFormatError", c.file_format.clone_ref(m.py()))?;
    m.add("MechanicsError", c.mechanics.clone_ref(m.py()))?;
    Ok(())
}

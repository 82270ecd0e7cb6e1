//! The Python exceptions of penedge and the one conversion from core errors to them.
//!
//! ```text
//! PenedgeError(Exception)                every error raised by penedge
//! ├── InputError(PenedgeError, ValueError)      wrong shape, dtype or value of an argument
//! ├── BlockError(PenedgeError, ValueError)      vertices + faces or half-spaces: not a convex block
//! └── ToleranceError(PenedgeError, ValueError)  impossible gap / length
//! ```
//!
//! Each exception carries `kind`, a snake_case name of what went wrong (`"not_convex"`,
//! `"out_of_range"`, `"shape"`, ...), so callers need not parse messages. The classes are made
//! once per process with `type(name, bases, dict)`, since PyO3's `create_exception!` takes one
//! base only.

use penedge::block::BlockError;
use penedge::generation::GenerationError;
use penedge::system::SystemError;
use penedge::tolerance::ToleranceError;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};

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
            SystemError::Generation(GenerationError::Cut { ref source, .. }) => {
                Error::Block(variant_name(source), e.to_string())
            }
            SystemError::Generation(GenerationError::Spec(_)) => {
                Error::Input("spec".into(), e.to_string())
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
        let (class, kind, message) = match &err {
            Error::Input(kind, m) => (&classes.input, kind, m),
            Error::Block(kind, m) => (&classes.block, kind, m),
            Error::Tolerance(kind, m) => (&classes.tolerance, kind, m),
        };
        instantiate(class.bind(py), kind, message).unwrap_or_else(|e| e)
    })
}

fn instantiate(class: &Bound<'_, PyType>, kind: &str, message: &str) -> PyResult<PyErr> {
    let value = class.call1((message,))?;
    value.setattr("kind", kind)?;
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
            "An impossible tolerance: gap or length not in [0, 0.1), or length < 10 * gap.",
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
    Ok(())
}

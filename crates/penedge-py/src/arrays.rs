//! numpy arrays in and out: array-likes of real numbers to Rust, Rust data to ndarrays.
//!
//! Input: anything `numpy.asarray` accepts whose dtype is integer, unsigned or float (bool,
//! complex, strings and objects are refused, not cast), of the expected shape. NaN and
//! infinities pass through: the core reports them with the index of the offending vertex or
//! plane.

use crate::errors::input_error;
use numpy::ndarray::{Array1, Array2};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayDescrMethods, PyReadonlyArrayDyn, PyUntypedArray,
    PyUntypedArrayMethods,
};
use penedge::glam::{DMat3, DQuat, DVec3};
use pyo3::prelude::*;

/// `numpy.asarray(obj)`, as an `InputError` naming `name` and what it should hold when
/// numpy cannot make an array of it. A masked array with a masked value is refused: asarray
/// would hand over the values under the mask as if they were given.
fn as_array<'py>(obj: &Bound<'py, PyAny>, name: &str, what: &str) -> PyResult<Bound<'py, PyAny>> {
    let numpy = obj.py().import("numpy")?;
    let ma = numpy.getattr("ma")?;
    if obj.is_instance(&ma.getattr("MaskedArray")?)?
        && ma.call_method1("is_masked", (obj,))?.is_truthy()?
    {
        let message = format!(
            "{name} has masked values: penedge reads no mask, so fill them (`.filled(x)`) or \
             leave those rows out"
        );
        return Err(input_error("masked", message));
    }
    numpy
        .getattr("asarray")?
        .call1((obj,))
        .map_err(|e| input_error("dtype", format!("{name} must be an array of {what}: {e}")))
}

/// Whether `obj` is a bool, Python's (an `int` to Python: `True == 1`) or numpy's
/// (`np.True_`, which converts to a number too; its type is `numpy.bool`, `numpy.bool_`
/// before numpy 2): penedge takes neither where a number or an id is expected.
pub fn is_bool(obj: &Bound<'_, PyAny>) -> bool {
    if obj.is_instance_of::<pyo3::types::PyBool>() {
        return true;
    }
    let ty = obj.get_type();
    if !ty.module().is_ok_and(|m| m == "numpy") {
        return false;
    }
    match ty.name() {
        Ok(n) if n == "bool" || n == "bool_" => true,
        // A numpy array of bools (`np.array(True)`, 0-d, read as a number otherwise).
        Ok(n) if n == "ndarray" => obj
            .getattr("dtype")
            .and_then(|d| d.getattr("kind"))
            .is_ok_and(|k| k.extract::<String>().is_ok_and(|k| k == "b")),
        _ => false,
    }
}

/// The `InputError` (kind ``dtype``) for the bool `value` given as argument `name`, where
/// `what` ("an integer", "a real number") is expected.
pub fn bool_error(name: &str, what: &str, value: &impl std::fmt::Display) -> PyErr {
    input_error(
        "dtype",
        format!("{name} must be {what}, got the bool {value}"),
    )
}

/// What a number argument of type `T` must be, for [`bool_error`]'s message.
pub trait NumberKind {
    /// "a real number", "an integer".
    const WHAT: &'static str;
}

impl NumberKind for f64 {
    const WHAT: &'static str = "a real number";
}

impl NumberKind for Whole {
    const WHAT: &'static str = "an integer";
}

/// A scalar number argument (a count, a step count, threads, a density, a stiffness, a
/// gap, a time) as Python gave it: its value, as `T` takes it (a float, an int, anything
/// with `__float__` or `__index__`), or a bool, which `T` would take as 0 or 1. The bool is
/// kept, not refused here: the function that takes the argument knows its name, and
/// [`Number::get`] refuses it as an `InputError` naming it, as a bool in a list of ids is
/// ([`refuse_bools`]). Another type (a string) is pyo3's `TypeError` naming the argument,
/// as before.
#[derive(Clone, Debug)]
pub enum Number<T> {
    /// A number.
    Value(T),
    /// A bool, Python's or numpy's: its text (``True``).
    Bool(String),
}

/// A real-number argument ([`Number`]).
pub type Real = Number<f64>;

/// A whole-number argument ([`Number`] of [`Whole`]).
pub type Count = Number<Whole>;

impl<'a, 'py, T> FromPyObject<'a, 'py> for Number<T>
where
    T: FromPyObject<'a, 'py>,
    T::Error: Into<PyErr>,
{
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if is_bool(&obj) {
            let text = obj
                .str()
                .map_or_else(|_| "?".to_string(), |s| s.to_string());
            return Ok(Number::Bool(text));
        }
        obj.extract::<T>().map(Number::Value).map_err(Into::into)
    }
}

impl<T: NumberKind> Number<T> {
    /// The number given as argument `name`; a bool is an `InputError` naming it.
    pub fn get(self, name: &str) -> PyResult<T> {
        match self {
            Number::Value(value) => Ok(value),
            Number::Bool(text) => Err(bool_error(name, T::WHAT, &text)),
        }
    }

    /// [`Number::get`] of an optional argument (`None` stays `None`).
    pub fn optional(value: Option<Self>, name: &str) -> PyResult<Option<T>> {
        value.map(|v| v.get(name)).transpose()
    }
}

/// A list or tuple holding a bool, Python's or numpy's, as an `InputError` naming `name`:
/// numpy would make 0 and 1 of it when other elements are integers (`[0, True]`).
fn refuse_bools(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<()> {
    let items = if let Ok(list) = obj.cast::<pyo3::types::PyList>() {
        list.iter().collect::<Vec<_>>()
    } else if let Ok(tuple) = obj.cast::<pyo3::types::PyTuple>() {
        tuple.iter().collect()
    } else {
        return Ok(());
    };
    for (i, item) in items.iter().enumerate() {
        if is_bool(item) {
            return Err(bool_error(&format!("{name}[{i}]"), "an integer", item));
        }
    }
    Ok(())
}

/// `obj` as float64 values with the given shape (`None` = any length along that axis).
fn float_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    shape: &[Option<usize>],
) -> PyResult<Vec<f64>> {
    let array = as_array(obj, name, "numbers")?;
    let untyped = array.cast::<PyUntypedArray>()?;
    let dtype = untyped.dtype();
    if !matches!(dtype.kind(), b'i' | b'u' | b'f') {
        let msg = format!("{name} must hold real numbers (int or float), got dtype {dtype}");
        return Err(input_error("dtype", msg));
    }
    check_shape(name, untyped.shape(), shape)?;
    let floats = array.call_method1("astype", ("float64",))?;
    let floats: PyReadonlyArrayDyn<'py, f64> = floats.extract()?;
    Ok(floats.as_array().iter().copied().collect())
}

fn check_shape(name: &str, got: &[usize], want: &[Option<usize>]) -> PyResult<()> {
    let fits =
        got.len() == want.len() && got.iter().zip(want).all(|(g, w)| w.is_none_or(|w| w == *g));
    if fits {
        return Ok(());
    }
    let dims: Vec<String> = want
        .iter()
        .map(|w| w.map_or("n".to_string(), |w| w.to_string()))
        .collect();
    let msg = format!(
        "{name} must have shape ({}{}), got shape {got:?}",
        dims.join(", "),
        if dims.len() == 1 { "," } else { "" }
    );
    Err(input_error("shape", msg))
}

/// An `(n, 3)` array-like as points.
pub fn points(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f64; 3]>> {
    let flat = float_array(obj, name, &[None, Some(3)])?;
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// An `(n, 4)` array-like as rows of four numbers (quaternions `x, y, z, w`).
pub fn quads(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f64; 4]>> {
    let flat = float_array(obj, name, &[None, Some(4)])?;
    Ok(flat
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect())
}

/// A `(3,)` array-like as one point.
pub fn point(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 3]> {
    let flat = float_array(obj, name, &[Some(3)])?;
    Ok([flat[0], flat[1], flat[2]])
}

/// A rotation given as a quaternion `x, y, z, w` (shape (4,), normalised here) or a
/// rotation matrix (shape (3, 3), orthonormal with determinant 1 within 1e-9).
pub fn rotation(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<DQuat> {
    let shape: Vec<usize> = obj
        .py()
        .import("numpy")?
        .getattr("shape")?
        .call1((obj,))?
        .extract()?;
    if shape == [3, 3] {
        let m = float_array(obj, name, &[Some(3), Some(3)])?;
        // Rows in, columns for glam.
        let matrix = DMat3::from_cols_slice(&m).transpose();
        let off = (matrix.transpose() * matrix - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .fold(0.0f64, |worst, x| worst.max(x.abs()));
        let det = matrix.determinant();
        if !(off <= 1e-9 && (det - 1.0).abs() <= 1e-9) {
            let msg = format!(
                "{name} must be a rotation matrix (orthonormal, determinant 1), got \
                 max |R^T R - I| = {off:.3e} and determinant {det}"
            );
            return Err(input_error("not_a_rotation", msg));
        }
        return Ok(DQuat::from_mat3(&matrix).normalize());
    }
    let q = float_array(obj, name, &[Some(4)]).map_err(|_| {
        let msg = format!(
            "{name} must be a quaternion x, y, z, w (shape (4,)) or a rotation matrix \
             (shape (3, 3)), got shape {shape:?}"
        );
        input_error("shape", msg)
    })?;
    let q = DQuat::from_xyzw(q[0], q[1], q[2], q[3]);
    // Normalised as a pose's rotation is (`Pose::new`): any finite non-zero multiple of a
    // quaternion is its rotation, 1e200 q and 1e-200 q too (dividing by the length gave
    // the zero quaternion for the first and refused the second as zero).
    match penedge::block::Pose::new(q, DVec3::ZERO) {
        Some(pose) => Ok(pose.rotation),
        None => {
            let msg = format!("{name} must be a non-zero finite quaternion, got {q:?}");
            Err(input_error("not_a_rotation", msg))
        }
    }
}

/// An `(n,)` array-like of non-negative whole numbers (offsets, indices); any integer
/// dtype, no floats.
pub fn indices(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<u64>> {
    refuse_bools(obj, name)?;
    let array = as_array(obj, name, "integers")?;
    let untyped = array.cast::<PyUntypedArray>()?;
    let dtype = untyped.dtype();
    let empty = untyped.shape() == [0];
    if !(matches!(dtype.kind(), b'i' | b'u') || empty) {
        let msg = format!("{name} must hold integers, got dtype {dtype}");
        return Err(input_error("dtype", msg));
    }
    check_shape(name, untyped.shape(), &[None])?;
    if dtype.kind() == b'u' {
        // As they are: through int64, 2**64 - 1 would read as -1.
        let ints = array.call_method1("astype", ("uint64",))?;
        let ints: PyReadonlyArrayDyn<'_, u64> = ints.extract()?;
        return Ok(ints.as_array().iter().copied().collect());
    }
    let ints = array.call_method1("astype", ("int64",))?;
    let ints: PyReadonlyArrayDyn<'_, i64> = ints.extract()?;
    ints.as_array()
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            u64::try_from(v)
                .map_err(|_| input_error("negative", format!("{name}[{i}] is {v}, below 0")))
        })
        .collect()
}

/// A `(6,)` array-like as six numbers (a stress tensor's components).
pub fn six(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 6]> {
    let v = float_array(obj, name, &[Some(6)])?;
    Ok([v[0], v[1], v[2], v[3], v[4], v[5]])
}

/// An `(n,)` array-like as numbers.
pub fn numbers(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    float_array(obj, name, &[None])
}

/// Plane normals `(m, 3)` and offsets `(m,)` of the same length.
pub fn planes(
    normals: &Bound<'_, PyAny>,
    offsets: &Bound<'_, PyAny>,
) -> PyResult<(Vec<[f64; 3]>, Vec<f64>)> {
    let normals = points(normals, "normals")?;
    let offsets = numbers(offsets, "offsets")?;
    if normals.len() != offsets.len() {
        let msg = format!(
            "normals and offsets must have the same length, got {} and {}",
            normals.len(),
            offsets.len()
        );
        return Err(input_error("shape", msg));
    }
    Ok((normals, offsets))
}

/// Rows of three floats as an `(n, 3)` float64 array.
pub fn rows3<'py>(py: Python<'py>, rows: &[[f64; 3]]) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((rows.len(), 3), |(i, k)| rows[i][k]).into_pyarray(py)
}

/// Rows of two values (ids) as an `(n, 2)` array.
pub fn pairs<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    rows: &[[T; 2]],
) -> Bound<'py, PyArray2<T>> {
    Array2::from_shape_fn((rows.len(), 2), |(i, k)| rows[i][k]).into_pyarray(py)
}

/// A vector as a one-dimensional array.
pub fn vector<'py, T: numpy::Element>(py: Python<'py>, values: Vec<T>) -> Bound<'py, PyArray1<T>> {
    Array1::from(values).into_pyarray(py)
}

/// Marks an array read-only (results that the caller should not change in place).
pub fn read_only<'py, A>(array: Bound<'py, A>) -> PyResult<Bound<'py, A>> {
    let flags = array.as_any().getattr("flags")?;
    flags.setattr("writeable", false)?;
    Ok(array)
}

/// Plain data (a report, statistics) as Python dicts, lists and numbers, through JSON.
pub fn to_python<'py>(
    py: Python<'py>,
    value: &(impl serde::Serialize + ?Sized),
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.getattr("loads")?.call1((text,))
}

/// A whole-number argument (a Python `int`, or anything with `__index__`): its value when
/// it fits an `i64`, else the number as given. pyo3's own conversion of an int beyond 64
/// bits raises a bare `OverflowError` that names no argument; with this the function that
/// takes it says which argument is out of range and what it takes. Another type (a float)
/// is the `TypeError` it was.
#[derive(Clone, Debug)]
pub enum Whole {
    /// Within an `i64`.
    Fits(i64),
    /// Beyond: whether it is negative, and its text (cut short when long).
    Beyond(bool, String),
}

impl<'a, 'py> FromPyObject<'a, 'py> for Whole {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        match obj.extract::<i64>() {
            Ok(n) => Ok(Whole::Fits(n)),
            Err(e) if e.is_instance_of::<pyo3::exceptions::PyOverflowError>(obj.py()) => {
                let negative = obj.lt(0)?;
                Ok(Whole::Beyond(negative, int_text(&obj)))
            }
            Err(e) => Err(e),
        }
    }
}

impl Whole {
    /// The value, when it fits an `i64`.
    pub fn value(&self) -> Option<i64> {
        match self {
            Whole::Fits(n) => Some(*n),
            Whole::Beyond(..) => None,
        }
    }

    /// Whether the number is below zero.
    pub fn is_negative(&self) -> bool {
        match self {
            Whole::Fits(n) => *n < 0,
            Whole::Beyond(negative, _) => *negative,
        }
    }
}

impl std::fmt::Display for Whole {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Whole::Fits(n) => write!(f, "{n}"),
            Whole::Beyond(_, text) => f.write_str(text),
        }
    }
}

/// A sequence index into `n` items, Python's way (negative from the end): `None` when out
/// of range, beyond 64 bits included (the caller's `IndexError`, as a list's).
pub fn index_in(index: &Whole, n: usize) -> Option<usize> {
    let i = index.value()?;
    let n = i64::try_from(n).ok()?;
    let i = if i < 0 { i + n } else { i };
    (0..n).contains(&i).then_some(i as usize)
}

/// An int's decimal text for a message: in full up to 40 digits, else its start and the
/// count of its digits (Python refuses to write an int of over 4300 digits: then its bits).
fn int_text(obj: &Bound<'_, PyAny>) -> String {
    let Ok(text) = obj.str().map(|s| s.to_string()) else {
        let bits = obj.call_method0("bit_length").map(|b| b.to_string());
        return format!("an int of {} bits", bits.unwrap_or_else(|_| "many".into()));
    };
    let digits = text.trim_start_matches('-').len();
    if digits <= 40 {
        return text;
    }
    let start: String = text.chars().take(20).collect();
    format!("{start}... ({digits} digits)")
}

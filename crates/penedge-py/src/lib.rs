//! Python bindings of penedge: the module `penedge._core`.
//!
//! Conversions only; every computation is in the core crate. The files mirror the core
//! modules: [`block`], [`tolerance`], [`classify`], [`contact`], [`overlap`], [`system`],
//! [`generation`], [`io`], [`mechanics`], plus [`arrays`] (numpy in and out) and [`errors`]
//! (the exception tree and the one
//! conversion from core errors). The doc comments are the Python docstrings (numpydoc).

#![warn(missing_docs)]

pub mod arrays;
pub mod block;
pub mod classify;
pub mod contact;
pub mod errors;
pub mod generation;
pub mod io;
pub mod mechanics;
pub mod overlap;
pub mod system;
pub mod tolerance;

use pyo3::prelude::*;

/// penedge core (Rust): convex blocks, pair contacts and block systems.
///
/// Import the public API from ``penedge``, not from here.
#[pymodule]
mod _core {
    use pyo3::prelude::*;

    #[pymodule_export]
    use crate::block::Block;
    #[pymodule_export]
    use crate::contact::{detect_pair, PairContact};
    #[pymodule_export]
    use crate::generation::generate;
    #[pymodule_export]
    use crate::io::{write_pvd, TimeSeries};
    #[pymodule_export]
    use crate::mechanics::Simulation;
    #[pymodule_export]
    use crate::overlap::overlap;
    #[pymodule_export]
    use crate::system::{
        paper_example, paper_example_planes, paper_table3, BlockArrays, BlockSystem, BodyContacts,
        ContactTracker, SystemContacts,
    };

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        super::add_constants(m)?;
        crate::errors::register(m)
    }
}

/// `n` followed by the noun, singular for 1 and plural otherwise ("1 contact", "2
/// contacts"), for the `repr`s.
pub fn counted(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

fn add_constants(m: &Bound<'_, PyModule>) -> PyResult<()> {
    use crate::classify::{contact_type_names, FEATURE_KINDS, PENETRATING, SEPARATED};
    use pyo3::types::PyTuple;
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("CONTACT_TYPES", PyTuple::new(py, contact_type_names())?)?;
    m.add("FEATURE_KINDS", PyTuple::new(py, FEATURE_KINDS)?)?;
    m.add("SEPARATED", SEPARATED)?;
    m.add("PENETRATING", PENETRATING)?;
    // One named code per type (VERTEX_VERTEX = 1 ... FACE_FACE = 7), as in `types` arrays.
    for (code, name) in (1i8..).zip(contact_type_names()) {
        m.add(name.to_uppercase().replace('-', "_"), code)?;
    }
    Ok(())
}

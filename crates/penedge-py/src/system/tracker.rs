//! `ContactTracker` (core `system::ContactTracker`): contacts over time steps.

use super::{BlockSystem, BodyContacts, SystemContacts};
use crate::arrays::{self, Real};
use crate::errors::input_error;
use crate::tolerance::tolerance;
use penedge::block::Pose;
use penedge::geometry::DVec3;
use penedge::glam::DQuat;
use penedge::system::{self, UpdateReport};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The contacts of a block system whose blocks move rigidly, updated step by step (for DEM
/// and DDA time stepping).
///
/// The broad phase is reused while no block has moved more than half the `skin` since it
/// was built, and pairs clearly apart or clearly overlapping are answered by a certificate
/// without a query (see ``docs/systems.md``). Each step's contacts are exactly those of
/// :meth:`BlockSystem.detect` on the moved blocks.
///
/// For a system with concave blocks (:meth:`BlockSystem.with_bodies`) the tracker also
/// keeps the contacts of the bodies, with their regions (:attr:`body_contacts`, as
/// :meth:`BlockSystem.detect_bodies` on the moved blocks: two bodies can touch in several
/// separate regions), and :attr:`contacts` holds the contacts between parts of different
/// bodies only. The parts of one body must be given one pose.
///
/// Parameters
/// ----------
/// system : BlockSystem
///     The blocks at their reference placement (the identity pose).
/// skin : float, default 0.0
///     Extra width of the broad phase's boxes (a length, ≥ 0): the larger, the longer the
///     broad phase is reused, the more candidate pairs it keeps.
/// gap : float, default 1e-12
///     Relative gap, as in :func:`detect_pair`.
/// length : float, optional
///     Relative length threshold, as in :func:`detect_pair`.
/// absolute_gap : float, optional
///     The gap as a length (model units) instead of `gap`, as in :func:`detect_pair`.
/// bodies : bool, optional
///     Whether to keep the contacts of the bodies (:attr:`body_contacts`); by default, when
///     the system has concave blocks. ``True`` on convex blocks gives one region per
///     touching pair, with its normal, distance and area (each queried touching pair then
///     costs its contact geometry too).
///
/// Raises
/// ------
/// InputError
///     A negative, NaN or infinite `skin`.
/// ToleranceError
///     Impossible `gap`, `length` or `absolute_gap`.
///
/// Examples
/// --------
/// >>> import numpy as np, penedge
/// >>> system = penedge.paper_example(1)
/// >>> tracker = penedge.ContactTracker(system, skin=0.1)
/// >>> len(tracker.contacts.pairs)
/// 28
/// >>> rotations = np.tile([0.0, 0.0, 0.0, 1.0], (len(system), 1))
/// >>> translations = np.zeros((len(system), 3))
/// >>> translations[0, 2] = -1e-3  # block 0 leaves the block above it
/// >>> report = tracker.update(rotations, translations)
/// >>> report["rebuilt"], len(tracker.contacts.pairs) < 28
/// (False, True)
///
/// A U-block of three parts (body 0) and a block sitting in its notch (body 1), lifted by
/// 1 mm off the notch's floor: it still touches both walls, two regions.
///
/// >>> c = penedge.Block.cuboid
/// >>> u = [c([0, 0, 0], [3, 1, 1]), c([0, 0, 1], [1, 1, 2]), c([2, 0, 1], [3, 1, 2])]
/// >>> system = penedge.BlockSystem(u + [c([1, 0, 1], [2, 1, 2])]).with_bodies([0, 0, 0, 1])
/// >>> tracker = penedge.ContactTracker(system, skin=0.1)
/// >>> tracker.body_contacts.regions.tolist()
/// [0, 1, 2]
/// >>> translations = np.zeros((4, 3))
/// >>> translations[3, 2] = 1e-3
/// >>> _ = tracker.update(np.tile([0.0, 0.0, 0.0, 1.0], (4, 1)), translations)
/// >>> found = tracker.body_contacts
/// >>> found.regions.tolist(), found.normals.round(9).tolist()
/// ([0, 1], [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
#[pyclass(module = "penedge", name = "ContactTracker")]
pub struct ContactTracker {
    inner: system::ContactTracker,
    /// The contacts as a Python object, made when first asked for after an update (a step
    /// of a DEM loop that does not read them pays no copy of a million contacts).
    contacts: Option<Py<SystemContacts>>,
    /// The same for the contacts of the bodies.
    body_contacts: Option<Py<BodyContacts>>,
}

#[pymethods]
impl ContactTracker {
    #[new]
    #[pyo3(signature = (system, skin = Real::Value(0.0), gap = Real::Value(1e-12), length = None,
        absolute_gap = None, bodies = None),
        text_signature = "(system, skin=0.0, gap=1e-12, length=None, absolute_gap=None, bodies=None)")]
    fn new(
        py: Python<'_>,
        system: &BlockSystem,
        skin: Real,
        gap: Real,
        length: Option<Real>,
        absolute_gap: Option<Real>,
        bodies: Option<bool>,
    ) -> PyResult<Self> {
        let skin = skin.get("skin")?;
        let tol = tolerance(gap, length, absolute_gap)?;
        let system = &system.inner;
        let bodies = bodies.unwrap_or(system.has_concave());
        if !bodies && system.has_concave() {
            let msg = "bodies=False on a system with concave blocks: its contacts are those \
                       of the bodies (leave bodies out or give True)";
            return Err(input_error("bodies", msg.to_string()));
        }
        let inner = py
            .detach(|| match bodies {
                true => system::ContactTracker::tracking_bodies(system, tol, skin),
                false => system::ContactTracker::new(system, tol, skin),
            })
            .map_err(|e| input_error("skin", e.to_string()))?;
        Ok(ContactTracker {
            inner,
            contacts: None,
            body_contacts: None,
        })
    }

    /// The contacts of the bodies at the current poses (a :class:`BodyContacts`, one row per
    /// region), or ``None`` when the tracker does not keep them (convex blocks, ``bodies``
    /// not given).
    #[getter]
    fn body_contacts(&mut self, py: Python<'_>) -> PyResult<Option<Py<BodyContacts>>> {
        if let Some(made) = &self.body_contacts {
            return Ok(Some(made.clone_ref(py)));
        }
        let Some(found) = self.inner.body_contacts() else {
            return Ok(None);
        };
        let made = Py::new(py, BodyContacts::from_core(py, found.clone())?)?;
        self.body_contacts = Some(made.clone_ref(py));
        Ok(Some(made))
    }

    /// The contacts at the current poses (a :class:`SystemContacts`, without geometry).
    #[getter]
    fn contacts(&mut self, py: Python<'_>) -> PyResult<Py<SystemContacts>> {
        if let Some(made) = &self.contacts {
            return Ok(made.clone_ref(py));
        }
        let made = contacts_of(py, &self.inner)?;
        self.contacts = Some(made.clone_ref(py));
        Ok(made)
    }

    /// Moves every block to a new pose and updates the contacts.
    ///
    /// Block ``i`` goes to ``rotations[i] * x + translations[i]`` of its reference
    /// coordinates ``x``. Runs without the GIL.
    ///
    /// Parameters
    /// ----------
    /// rotations : array_like, shape (n, 4)
    ///     Unit quaternions ``x, y, z, w`` (normalised here), one per block.
    /// translations : array_like, shape (n, 3)
    ///     Translations, one per block.
    ///
    /// Returns
    /// -------
    /// dict
    ///     ``rebuilt`` (whether the broad phase ran again), ``candidate_pairs``,
    ///     ``unmoved`` (pairs answered because neither block moved since their last
    ///     query), ``certified`` (pairs answered by a certificate) and ``queried``.
    ///
    /// Raises
    /// ------
    /// InputError
    ///     Wrong shapes or dtypes, not one pose per block, NaN or infinite values, a zero
    ///     quaternion, two parts of one body with different poses (rotations are compared,
    ///     not quaternions: ``q``, ``-q`` and ``3 q`` are one rotation, and equal within
    ///     4 units of ``2**-52`` per component once normalised and turned to one sign;
    ///     the parts are then placed at the first part's pose), a translation that
    ///     could carry a block's coordinates beyond what double precision holds for it
    ///     (the rule of :meth:`Block.translated`: its closest vertices rounded together,
    ///     or past 1e50; the message names the block). The tracker is unchanged.
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        rotations: &Bound<'py, PyAny>,
        translations: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let rotations = arrays::quads(rotations, "rotations")?;
        let translations = arrays::points(translations, "translations")?;
        if rotations.len() != translations.len() {
            let msg = format!(
                "{} rotations but {} translations",
                rotations.len(),
                translations.len()
            );
            return Err(input_error("shape", msg));
        }
        let poses: Vec<Pose> = rotations
            .iter()
            .zip(&translations)
            .map(|(&[x, y, z, w], &t)| Pose {
                rotation: DQuat::from_xyzw(x, y, z, w),
                translation: DVec3::from_array(t),
            })
            .collect();
        let inner = &mut self.inner;
        let report: UpdateReport = py
            .detach(|| inner.update(&poses))
            .map_err(|e| input_error("pose", e.to_string()))?;
        self.contacts = None;
        self.body_contacts = None;
        let out = PyDict::new(py);
        out.set_item("rebuilt", report.rebuilt)?;
        out.set_item("candidate_pairs", report.candidate_pairs)?;
        out.set_item("unmoved", report.unmoved)?;
        out.set_item("certified", report.certified)?;
        out.set_item("queried", report.queried)?;
        Ok(out)
    }

    fn __repr__(&self) -> String {
        format!(
            "ContactTracker({}, {})",
            crate::counted(self.inner.len(), "block", "blocks"),
            crate::counted(self.inner.contacts().contacts.len(), "contact", "contacts")
        )
    }
}

fn contacts_of(py: Python<'_>, tracker: &system::ContactTracker) -> PyResult<Py<SystemContacts>> {
    Py::new(
        py,
        SystemContacts::from_core(py, tracker.contacts().clone(), None, None)?,
    )
}

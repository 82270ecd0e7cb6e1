//! A block system's blocks as flat numpy arrays (core `SystemArrays`), its volume statistics
//! (core `generation::BlockStatistics`) and where it came from (domain, spec entries).

use super::BlockSystem;
use crate::arrays;
use crate::block::Block;
use numpy::{PyArray1, PyArray2};
use penedge::generation::{distribution_curve, BlockStatistics};
use penedge::system::SystemArrays;
use pyo3::prelude::*;

/// Every block of a system as flat numpy arrays (read-only), from :meth:`BlockSystem.arrays`.
///
/// Block ``i`` owns the vertices ``vertices[vertex_offsets[i]:vertex_offsets[i + 1]]`` and
/// the faces ``face_offsets[i]:face_offsets[i + 1]``; face ``f`` is the loop
/// ``face_vertices[loop_offsets[f]:loop_offsets[f + 1]]`` of indices into `vertices`,
/// counter-clockwise seen from outside.
///
/// Attributes
/// ----------
/// vertices : numpy.ndarray, shape (v, 3), float64
///     All vertices, block after block (blocks do not share vertices).
/// vertex_offsets : numpy.ndarray, shape (n + 1,), int64
/// face_offsets : numpy.ndarray, shape (n + 1,), int64
/// loop_offsets : numpy.ndarray, shape (f + 1,), int64
/// face_vertices : numpy.ndarray, shape (l,), int64
///     Vertex loops of all faces (indices into `vertices`).
/// face_normals : numpy.ndarray, shape (f, 3), float64
///     Outward unit normal of each face.
/// face_block : numpy.ndarray, shape (f,), int64
///     The block of each face.
/// face_origin_kind : numpy.ndarray, shape (f,), int8
///     Where each face comes from: 0 unknown, 1 domain boundary (a free face), 2 joint,
///     3 rock bridge.
/// face_origin_set : numpy.ndarray, shape (f,), int64
///     Domain part (boundary) or spec entry (joint; an index into :attr:`BlockSystem.sets`);
///     -1 when unknown.
/// face_origin_index : numpy.ndarray, shape (f,), int64
///     Face of the domain part (boundary) or joint plane (joint); -1 when unknown.
/// volumes : numpy.ndarray, shape (n,), float64
/// centroids : numpy.ndarray, shape (n, 3), float64
/// body_ids : numpy.ndarray, shape (n,), int64
///     The body (concave block) of each block; its own id unless given by
///     :meth:`BlockSystem.with_bodies`.
/// face_internal : numpy.ndarray, shape (f,), int8
///     1 for a face inside its concave block (glued to other parts entirely), else 0.
#[pyclass(module = "penedge", name = "BlockArrays", frozen, get_all)]
pub struct BlockArrays {
    vertices: Py<PyArray2<f64>>,
    vertex_offsets: Py<PyArray1<i64>>,
    face_offsets: Py<PyArray1<i64>>,
    loop_offsets: Py<PyArray1<i64>>,
    face_vertices: Py<PyArray1<i64>>,
    face_normals: Py<PyArray2<f64>>,
    face_block: Py<PyArray1<i64>>,
    face_origin_kind: Py<PyArray1<i8>>,
    face_origin_set: Py<PyArray1<i64>>,
    face_origin_index: Py<PyArray1<i64>>,
    volumes: Py<PyArray1<f64>>,
    centroids: Py<PyArray2<f64>>,
    body_ids: Py<PyArray1<i64>>,
    face_internal: Py<PyArray1<i8>>,
}

fn signed(values: &[u64]) -> Vec<i64> {
    values.iter().map(|&v| v as i64).collect()
}

/// The block id of each face, from the per-block face offsets.
fn face_blocks(face_offsets: &[u64]) -> Vec<i64> {
    let mut out = Vec::with_capacity(face_offsets.last().copied().unwrap_or(0) as usize);
    for (block, w) in face_offsets.windows(2).enumerate() {
        out.extend(std::iter::repeat_n(block as i64, (w[1] - w[0]) as usize));
    }
    out
}

impl BlockArrays {
    fn new(py: Python<'_>, a: SystemArrays) -> PyResult<Self> {
        let v1 = |v: Vec<i64>| Ok::<_, PyErr>(arrays::read_only(arrays::vector(py, v))?.unbind());
        let rows =
            |r: &[[f64; 3]]| Ok::<_, PyErr>(arrays::read_only(arrays::rows3(py, r))?.unbind());
        let kinds = a.origin_kind.iter().map(|&k| k as i8).collect();
        let internal = a.face_internal.iter().map(|&k| k as i8).collect();
        Ok(BlockArrays {
            vertices: rows(&a.vertices)?,
            vertex_offsets: v1(signed(&a.vertex_offsets))?,
            face_offsets: v1(signed(&a.face_offsets))?,
            loop_offsets: v1(signed(&a.loop_offsets))?,
            face_vertices: v1(signed(&a.face_vertices))?,
            face_normals: rows(&a.face_normals)?,
            face_block: v1(face_blocks(&a.face_offsets))?,
            face_origin_kind: arrays::read_only(arrays::vector(py, kinds))?.unbind(),
            face_origin_set: v1(a.origin_set)?,
            face_origin_index: v1(a.origin_index)?,
            volumes: arrays::read_only(arrays::vector(py, a.volumes))?.unbind(),
            centroids: rows(&a.centroids)?,
            body_ids: v1(a.body_ids)?,
            face_internal: arrays::read_only(arrays::vector(py, internal))?.unbind(),
        })
    }
}

#[pymethods]
impl BlockArrays {
    fn __repr__(&self, py: Python<'_>) -> String {
        let len = |a: &Py<PyArray1<f64>>| a.bind(py).len().unwrap_or(0);
        let faces = self.face_block.bind(py).len().unwrap_or(0);
        format!(
            "BlockArrays({}, {})",
            crate::counted(len(&self.volumes), "block", "blocks"),
            crate::counted(faces, "face", "faces")
        )
    }
}

impl BlockSystem {
    /// The volume of each block, a concave block's parts summed (by ascending body id); for
    /// a system of convex blocks, each block's volume.
    fn block_volumes(&self) -> Vec<f64> {
        let blocks = self.inner.blocks();
        if !self.inner.has_concave() {
            return blocks.iter().map(|b| b.volume()).collect();
        }
        self.inner
            .body_parts()
            .iter()
            .map(|(_, parts)| parts.iter().map(|&k| blocks[k as usize].volume()).sum())
            .collect()
    }
}

#[pymethods]
impl BlockSystem {
    /// Every block as flat arrays: vertices, faces, normals, face origins, volumes,
    /// centroids (see :class:`BlockArrays`).
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> a = penedge.paper_example(1).arrays()
    /// >>> a.vertices.shape, a.face_offsets[-1], a.volumes.sum()
    /// ((64, 3), np.int64(48), np.float64(1000.0))
    /// >>> first = a.face_vertices[a.loop_offsets[0]:a.loop_offsets[1]]
    /// >>> a.vertices[first].tolist()  # block 0, face 0: its bottom (z = 0)
    /// [[0.0, 0.0, 0.0], [0.0, 5.0, 0.0], [5.0, 5.0, 0.0], [5.0, 0.0, 0.0]]
    fn arrays(&self, py: Python<'_>) -> PyResult<BlockArrays> {
        let inner = &self.inner;
        let a = py.detach(|| inner.arrays());
        BlockArrays::new(py, a)
    }

    /// Block volumes, shape (n,).
    #[getter]
    fn volumes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::vector(py, self.inner.blocks().iter().map(|b| b.volume()).collect())
    }

    /// Block centroids, shape (n, 3).
    #[getter]
    fn centroids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let rows: Vec<[f64; 3]> = self
            .inner
            .blocks()
            .iter()
            .map(|b| b.centroid().to_array())
            .collect();
        arrays::rows3(py, &rows)
    }

    /// Block count and volume distribution, or None for an empty system.
    ///
    /// ``v10``, ``v50``, ``v90`` are sieve-curve passing volumes: ``vX`` is the smallest block
    /// volume such that blocks no larger hold at least X % of the rock volume;
    /// ``count_percentiles`` are the 10th, 50th and 90th percentile volumes by block count.
    ///
    /// A block is a body: the convex parts of a concave block (the parts that share a body
    /// id, :attr:`BlockSystem.body_ids`) count as one block, of their volumes summed, so
    /// ``count`` is the number of bodies (``len(system)`` counts the parts). For a system of
    /// convex blocks, every block is one.
    ///
    /// Returns
    /// -------
    /// dict or None
    ///     Keys ``count``, ``total_volume``, ``min_volume``, ``max_volume``, ``mean_volume``,
    ///     ``v10``, ``v50``, ``v90``, ``count_percentiles``.
    ///
    /// Examples
    /// --------
    /// >>> import penedge
    /// >>> s = penedge.paper_example(3).statistics()
    /// >>> s["count"], round(s["v10"], 2), round(s["v50"], 2), s["v90"]
    /// (26, 20.83, 41.67, 125.0)
    fn statistics<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        BlockStatistics::of_volumes(&self.block_volumes())
            .map(|s| arrays::to_python(py, &s))
            .transpose()
    }

    /// The cumulative volume curve: block volumes in increasing order, and for each the
    /// fraction of the total volume in blocks no larger (what the volume distribution
    /// picture plots). Per block, as :meth:`BlockSystem.statistics`: the parts of a concave
    /// block count as one block.
    ///
    /// Returns
    /// -------
    /// volumes : numpy.ndarray, shape (n,)
    /// passing : numpy.ndarray, shape (n,)
    ///     Increasing, the last is 1.
    fn volume_curve<'py>(
        &self,
        py: Python<'py>,
    ) -> (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>) {
        let curve = distribution_curve(&self.block_volumes());
        let (v, p) = curve.iter().map(|c| (c.volume, c.passing)).unzip();
        (arrays::vector(py, v), arrays::vector(py, p))
    }

    /// The entries of the generation spec, in order: ``{"name": ..., "kind": ...}`` with kind
    /// ``"plane"``, ``"set"``, ``"disc"``, ``"polygon"`` or ``"excavation"`` (an
    /// ``[[excavations]]`` entry: the faces it makes are the opening's walls, free faces)
    /// (empty when not generated). ``BlockArrays.face_origin_set`` of a joint face indexes
    /// this list.
    #[getter]
    fn sets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        arrays::to_python(py, self.inner.sets())
    }

    /// The convex parts of the domain (empty when not known).
    #[getter]
    fn domain(&self) -> Vec<Block> {
        self.inner
            .domain()
            .iter()
            .cloned()
            .map(Block::wrap)
            .collect()
    }
}

//! ParaView time series: PVD collection files (`.pvd`) and a writer of blocks and contacts
//! step after step.
//!
//! A PVD file is a VTK XML `Collection` that lists one dataset file per time step
//! (`<DataSet timestep="0.5" file="blocks_000001.vtu"/>`); ParaView opens it as one source
//! with a time slider. [`write_pvd`] writes such an index for files written by anyone;
//! [`TimeSeries`] writes, for each step, the blocks as VTU ([`super::vtu`]) and optionally
//! the contacts as VTP ([`super::vtp`]) into one folder and keeps two indexes up to date:
//!
//! ```text
//! series/
//!   blocks.pvd            step 0, 1, 2, ... -> blocks_000000.vtu, blocks_000001.vtu, ...
//!   contacts.pvd          the steps written with contacts -> contacts_000000.vtp, ...
//!   blocks_000000.vtu
//!   contacts_000000.vtp
//!   ...
//! ```
//!
//! Every file, index included, is written atomically, and a step's data files are written
//! before the indexes that list them: a reader (ParaView, with the series open while a
//! simulation runs) sees complete steps only, and a run that stops half-way leaves a series
//! that [`TimeSeries::open`] resumes at the last complete step.
//!
//! Times must be finite and strictly increasing. File names in an index are relative to the
//! index's folder (as ParaView reads them).

use super::{read_text, vtp, vtu, write_atomic, IoError};
use crate::system::{BlockSystem, ContactGeometries, SystemContacts};
use std::fmt;
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// One dataset of a PVD collection: its time and its file.
#[derive(Clone, Debug, PartialEq)]
pub struct PvdEntry {
    /// The time step (finite).
    pub time: f64,
    /// The file, relative to the folder of the `.pvd` (or absolute).
    pub file: String,
}

/// Why a time step or a collection was refused (nothing is written then), or could not be
/// written.
#[derive(Debug, Error)]
pub enum SeriesError {
    /// A time that is not finite, or not after the previous one.
    #[error("{0}")]
    Time(String),
    /// An empty file name in a collection.
    #[error("{0}")]
    FileName(String),
    /// Contacts that do not belong to the system, or a geometry of other contacts.
    #[error("{0}")]
    Mismatch(String),
    /// A file could not be read or written, or an index to resume is not valid.
    #[error(transparent)]
    Io(#[from] IoError),
}

/// Checks that the times are finite and strictly increasing.
fn check_times(times: impl IntoIterator<Item = f64>) -> Result<(), SeriesError> {
    let mut last: Option<f64> = None;
    for (k, t) in times.into_iter().enumerate() {
        check_next_time(t, last).map_err(|e| SeriesError::Time(format!("dataset {k}: {e}")))?;
        last = Some(t);
    }
    Ok(())
}

/// A new time after `last`: finite and greater.
fn check_next_time(time: f64, last: Option<f64>) -> Result<(), SeriesError> {
    if !time.is_finite() {
        return Err(SeriesError::Time(format!(
            "the time must be finite, got {time}"
        )));
    }
    match last {
        Some(last) if time <= last => Err(SeriesError::Time(format!(
            "the times must increase: {time:?} is not after {last:?}"
        ))),
        _ => Ok(()),
    }
}

/// Writes a PVD collection listing `entries`, atomically.
///
/// Refused ([`SeriesError::Time`], [`SeriesError::FileName`]) before anything is written when a
/// time is not finite, the times do not strictly increase, or a file name is empty.
pub fn write_pvd(path: &Path, entries: &[PvdEntry]) -> Result<(), SeriesError> {
    check_times(entries.iter().map(|e| e.time))?;
    if let Some(k) = entries.iter().position(|e| e.file.is_empty()) {
        return Err(SeriesError::FileName(format!(
            "dataset {k}: empty file name"
        )));
    }
    Ok(write_atomic(path, |w| write_pvd_to(entries, w))?)
}

/// The PVD collection, to any writer (no check of the times).
pub fn write_pvd_to(entries: &[PvdEntry], w: &mut dyn Write) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">"
    )?;
    writeln!(w, "<Collection>")?;
    for e in entries {
        writeln!(
            w,
            "<DataSet timestep=\"{:?}\" group=\"\" part=\"0\" file=\"{}\"/>",
            e.time,
            Escaped(&e.file)
        )?;
    }
    writeln!(w, "</Collection>\n</VTKFile>")
}

/// Reads the datasets of a PVD collection (as written by [`write_pvd`], or by ParaView),
/// in file order.
///
/// A file that is not a VTK `Collection` is an [`IoError::Format`]; a `DataSet` without a
/// `file`, or with a `timestep` that is not a number, an [`IoError::Format`] naming it
/// (`DataSet[2].timestep`). A dataset without `timestep` gets time 0, as in ParaView.
pub fn read_pvd(path: &Path) -> Result<Vec<PvdEntry>, IoError> {
    let text = read_text(path)?;
    let format = |field: String, message: String| IoError::Format {
        field: format!("{}: {field}", path.display()),
        message,
    };
    let root = tags(&text, "VTKFile").next();
    match root.map(|attrs| attribute(attrs, "type")) {
        Some(Some(kind)) if kind == "Collection" => {}
        _ => {
            return Err(format(
                "VTKFile.type".into(),
                "not a VTK collection (.pvd) file".into(),
            ))
        }
    }
    let mut out = Vec::new();
    for (k, attrs) in tags(&text, "DataSet").enumerate() {
        let time = match attribute(attrs, "timestep") {
            None => 0.0,
            Some(t) => t.trim().parse::<f64>().map_err(|_| {
                format(
                    format!("DataSet[{k}].timestep"),
                    format!("not a number: {t:?}"),
                )
            })?,
        };
        let file = attribute(attrs, "file")
            .filter(|f| !f.is_empty())
            .ok_or_else(|| format(format!("DataSet[{k}].file"), "missing".into()))?;
        out.push(PvdEntry { time, file });
    }
    Ok(out)
}

/// The attribute text of every `<name ...>` tag of `text`.
fn tags<'a>(text: &'a str, name: &str) -> impl Iterator<Item = &'a str> {
    let open = format!("<{name}");
    let found: Vec<&str> = text
        .match_indices(open.as_str())
        .filter_map(|(start, _)| {
            let rest = &text[start + open.len()..];
            // `<DataSetX` is another tag.
            if !rest.starts_with(|c: char| c.is_whitespace() || c == '/' || c == '>') {
                return None;
            }
            rest.find('>').map(|end| rest[..end].trim_end_matches('/'))
        })
        .collect();
    found.into_iter()
}

/// The unescaped value of attribute `name` in a tag's attribute text.
fn attribute(attrs: &str, name: &str) -> Option<String> {
    let mut rest = attrs;
    loop {
        rest = rest.trim_start();
        let eq = rest.find('=')?;
        let key = rest[..eq].trim();
        let after = rest[eq + 1..].trim_start();
        let quote = after.chars().next().filter(|&q| q == '"' || q == '\'')?;
        let close = after[1..].find(quote)?;
        if key == name {
            return Some(unescape(&after[1..1 + close]));
        }
        rest = &after[close + 2..];
    }
}

/// A string escaped for an XML attribute value.
struct Escaped<'a>(&'a str);

impl fmt::Display for Escaped<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for c in self.0.chars() {
            match c {
                '&' => f.write_str("&amp;")?,
                '<' => f.write_str("&lt;")?,
                '>' => f.write_str("&gt;")?,
                '"' => f.write_str("&quot;")?,
                '\'' => f.write_str("&apos;")?,
                c => write!(f, "{c}")?,
            }
        }
        Ok(())
    }
}

fn unescape(s: &str) -> String {
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

/// The blocks and contacts of a simulation, step after step, as a ParaView time series in
/// one folder (see the [module documentation](self)).
///
/// ```
/// use penedge::io::pvd::{read_pvd, TimeSeries};
/// use penedge::system::{paper_example, PaperExample};
/// use penedge::Tolerance;
///
/// let folder = std::env::temp_dir().join(format!("penedge-doc-series-{}", std::process::id()));
/// let system = paper_example(PaperExample::One).unwrap();
/// let mut series = TimeSeries::create(&folder).unwrap();
/// for step in 0..3 {
///     // ... a simulation moves the blocks ...
///     let (found, geometry) = system.detect_with_geometry(&Tolerance::default());
///     series.write_step(0.1 * step as f64, &system, Some((&found, &geometry))).unwrap();
/// }
/// // ParaView: File > Open > blocks.pvd and contacts.pvd of the folder
/// let steps = read_pvd(&folder.join("blocks.pvd")).unwrap();
/// assert_eq!(steps[2].file, "blocks_000002.vtu");
/// # std::fs::remove_dir_all(&folder).unwrap();
/// ```
#[derive(Clone, Debug)]
pub struct TimeSeries {
    folder: PathBuf,
    blocks: Vec<PvdEntry>,
    contacts: Vec<PvdEntry>,
}

impl TimeSeries {
    /// The index of the block files, in the series' folder.
    pub const BLOCKS_INDEX: &'static str = "blocks.pvd";
    /// The index of the contact files, in the series' folder.
    pub const CONTACTS_INDEX: &'static str = "contacts.pvd";

    /// Starts a new series in `folder` (made if missing, with its parents) and writes its two
    /// empty indexes.
    ///
    /// A folder that already holds a series (either index) is refused with an
    /// [`IoError::Io`] of kind `AlreadyExists`: resume it with [`TimeSeries::open`], or
    /// choose another folder; nothing is replaced.
    pub fn create(folder: &Path) -> Result<TimeSeries, IoError> {
        fs::create_dir_all(folder).map_err(|e| IoError::io(folder, e))?;
        let series = TimeSeries {
            folder: folder.to_path_buf(),
            blocks: Vec::new(),
            contacts: Vec::new(),
        };
        for index in [series.blocks_index(), series.contacts_index()] {
            if index.exists() {
                let message = "a time series is already there (resume it, or use another folder)";
                return Err(IoError::io(
                    &index,
                    io::Error::new(io::ErrorKind::AlreadyExists, message),
                ));
            }
        }
        series.write_indexes(true)?;
        Ok(series)
    }

    /// Resumes the series in `folder`: reads its indexes, and the next step continues after
    /// the last one listed (files of a step that never reached the index are replaced).
    ///
    /// A missing `blocks.pvd` is an [`IoError::Io`] (`NotFound`); an index that is not a
    /// collection, or whose times are not finite and increasing, an [`IoError::Format`]. A
    /// missing `contacts.pvd` (a series written without contacts) is an empty one.
    pub fn open(folder: &Path) -> Result<TimeSeries, IoError> {
        let mut series = TimeSeries {
            folder: folder.to_path_buf(),
            blocks: Vec::new(),
            contacts: Vec::new(),
        };
        series.blocks = read_pvd(&series.blocks_index())?;
        let contacts = series.contacts_index();
        if contacts.exists() {
            series.contacts = read_pvd(&contacts)?;
        }
        for (entries, index) in [
            (&series.blocks, series.blocks_index()),
            (&series.contacts, contacts),
        ] {
            check_times(entries.iter().map(|e| e.time)).map_err(|e| IoError::Format {
                field: format!("{}: timestep", index.display()),
                message: e.to_string(),
            })?;
        }
        if let Some(c) = series.contacts.last() {
            if series.blocks.last().is_none_or(|b| c.time > b.time) {
                return Err(IoError::Format {
                    field: format!("{}: timestep", series.contacts_index().display()),
                    message: format!("contacts at time {:?} after the last blocks", c.time),
                });
            }
        }
        Ok(series)
    }

    /// Writes one step: the blocks as `blocks_NNNNNN.vtu`, the contacts (when given, with
    /// their geometry from [`BlockSystem::detect_with_geometry`]) as `contacts_NNNNNN.vtp`,
    /// then the indexes; returns the step number `NNNNNN` (0, 1, 2, ...).
    ///
    /// Refused before anything is written when the time is not finite or not after the
    /// previous step's, when the geometry does not belong to the contacts, or the contacts
    /// name a block the system does not have.
    pub fn write_step(
        &mut self,
        time: f64,
        system: &BlockSystem,
        contacts: Option<(&SystemContacts, &ContactGeometries)>,
    ) -> Result<usize, SeriesError> {
        check_next_time(time, self.blocks.last().map(|e| e.time))?;
        if let Some((found, geometry)) = contacts {
            check_contacts(system, found, geometry)?;
        }
        let step = self.blocks.len();
        let blocks_file = format!("blocks_{step:06}.vtu");
        vtu::write_vtu(system, &self.folder.join(&blocks_file))?;
        if let Some((found, geometry)) = contacts {
            let file = format!("contacts_{step:06}.vtp");
            vtp::write_contacts_vtp(found, geometry, &self.folder.join(&file))?;
            self.contacts.push(PvdEntry { time, file });
        }
        self.blocks.push(PvdEntry {
            time,
            file: blocks_file,
        });
        let written = self.write_indexes(contacts.is_some());
        if let Err(e) = written {
            // The step is not in the series: the next step takes its number and rewrites
            // both indexes from these lists.
            self.blocks.pop();
            if contacts.is_some() {
                self.contacts.pop();
            }
            return Err(e.into());
        }
        Ok(step)
    }

    /// Rewrites `blocks.pvd`, then `contacts.pvd` when `contacts`. In this order a run that
    /// stops between the two leaves a step without contacts, which [`TimeSeries::open`]
    /// accepts (contacts listed after the last blocks would not be).
    fn write_indexes(&self, contacts: bool) -> Result<(), IoError> {
        write_atomic(&self.blocks_index(), |w| write_pvd_to(&self.blocks, w))?;
        if contacts {
            write_atomic(&self.contacts_index(), |w| write_pvd_to(&self.contacts, w))?;
        }
        Ok(())
    }

    /// The series' folder.
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// The path of `blocks.pvd`.
    pub fn blocks_index(&self) -> PathBuf {
        self.folder.join(Self::BLOCKS_INDEX)
    }

    /// The path of `contacts.pvd`.
    pub fn contacts_index(&self) -> PathBuf {
        self.folder.join(Self::CONTACTS_INDEX)
    }

    /// The datasets of `blocks.pvd`: one per step.
    pub fn blocks(&self) -> &[PvdEntry] {
        &self.blocks
    }

    /// The datasets of `contacts.pvd`: one per step written with contacts.
    pub fn contacts(&self) -> &[PvdEntry] {
        &self.contacts
    }

    /// The number of steps written.
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// Whether no step has been written.
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }
}

/// The contacts and their geometry belong together and to `system`.
fn check_contacts(
    system: &BlockSystem,
    found: &SystemContacts,
    geometry: &ContactGeometries,
) -> Result<(), SeriesError> {
    let rows = geometry.len();
    if found.contacts.len() != rows || geometry.point_offsets.len() != rows + 1 {
        return Err(SeriesError::Mismatch(format!(
            "the geometry has {rows} rows for {} contacts",
            found.contacts.len()
        )));
    }
    let n = system.len();
    let beyond = |p: &[u32; 2]| p[1] as usize >= n;
    if let Some(pc) = found.contacts.iter().find(|pc| beyond(&pc.pair)) {
        let [a, b] = pc.pair;
        return Err(SeriesError::Mismatch(format!(
            "the contacts are not of this system: pair ({a}, {b}) for {n} blocks"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{paper_example, PaperExample};
    use crate::Tolerance;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("penedge-pvd-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        dir
    }

    fn entry(time: f64, file: &str) -> PvdEntry {
        PvdEntry {
            time,
            file: file.into(),
        }
    }

    #[test]
    fn a_collection_reads_back_with_escaped_names_and_exact_times() {
        let dir = scratch("round-trip");
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join("series.pvd");
        let entries = [
            entry(0.0, "a&b <1>.vtu"),
            entry(1e-300, "x.vtp"),
            entry(0.1, "it's \"2\".vtu"),
        ];
        write_pvd(&path, &entries).unwrap();
        let text = fs::read_to_string(&path).unwrap();
        assert!(text.contains("file=\"a&amp;b &lt;1&gt;.vtu\""), "{text}");
        assert!(text.contains("<DataSet timestep=\"1e-300\""), "{text}");
        assert_eq!(read_pvd(&path).unwrap(), entries);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_times_and_names_are_refused_before_writing() {
        let path = scratch("refused.pvd");
        let cases = [
            (
                vec![entry(f64::NAN, "a.vtu")],
                "dataset 0: the time must be finite, got NaN",
            ),
            (
                vec![entry(1.0, "a.vtu"), entry(1.0, "b.vtu")],
                "dataset 1: the times must increase: 1.0 is not after 1.0",
            ),
            (vec![entry(0.0, "")], "dataset 0: empty file name"),
        ];
        for (entries, message) in cases {
            let err = write_pvd(&path, &entries).unwrap_err();
            assert_eq!(err.to_string(), message);
            assert!(!path.exists());
        }
    }

    #[test]
    fn a_file_that_is_not_a_collection_is_a_format_error() {
        let dir = scratch("not-pvd");
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join("x.pvd");
        for (text, field) in [
            ("<VTKFile type=\"PolyData\"></VTKFile>", "VTKFile.type"),
            (
                "<VTKFile type=\"Collection\"><Collection><DataSet timestep=\"x\" file=\"a\"/>",
                "DataSet[0].timestep",
            ),
            (
                "<VTKFile type='Collection'><DataSet timestep='1'/></VTKFile>",
                "DataSet[0].file",
            ),
        ] {
            fs::write(&path, text).unwrap();
            match read_pvd(&path).unwrap_err() {
                IoError::Format { field: f, .. } => assert!(f.ends_with(field), "{f}"),
                other => panic!("{other}"),
            }
        }
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_series_lists_complete_steps_and_resumes() {
        let dir = scratch("series");
        let system = paper_example(PaperExample::One).unwrap();
        let (found, geometry) = system.detect_with_geometry(&Tolerance::default());
        let mut series = TimeSeries::create(&dir).unwrap();
        assert_eq!(read_pvd(&series.blocks_index()).unwrap(), []);
        assert_eq!(
            series
                .write_step(0.0, &system, Some((&found, &geometry)))
                .unwrap(),
            0
        );
        assert_eq!(series.write_step(0.5, &system, None).unwrap(), 1);
        let err = series.write_step(0.5, &system, None).unwrap_err();
        assert!(matches!(err, SeriesError::Time(_)), "{err}");
        assert!(!dir.join("blocks_000002.vtu").exists());

        let blocks = read_pvd(&dir.join("blocks.pvd")).unwrap();
        assert_eq!(
            blocks,
            [
                entry(0.0, "blocks_000000.vtu"),
                entry(0.5, "blocks_000001.vtu")
            ]
        );
        let contacts = read_pvd(&dir.join("contacts.pvd")).unwrap();
        assert_eq!(contacts, [entry(0.0, "contacts_000000.vtp")]);
        for e in blocks.iter().chain(&contacts) {
            assert!(dir.join(&e.file).is_file(), "{}", e.file);
        }

        let again = TimeSeries::create(&dir).unwrap_err();
        assert!(again.to_string().contains("a time series is already there"));
        let mut resumed = TimeSeries::open(&dir).unwrap();
        assert_eq!((resumed.len(), resumed.contacts().len()), (2, 1));
        let step = resumed
            .write_step(0.75, &system, Some((&found, &geometry)))
            .unwrap();
        assert_eq!(step, 2);
        assert_eq!(
            read_pvd(&dir.join("contacts.pvd")).unwrap()[1],
            entry(0.75, "contacts_000002.vtp")
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn contacts_of_another_system_are_refused() {
        let dir = scratch("mismatch");
        let small = paper_example(PaperExample::One).unwrap();
        let big = paper_example(PaperExample::Three).unwrap();
        let (found, geometry) = big.detect_with_geometry(&Tolerance::default());
        let mut series = TimeSeries::create(&dir).unwrap();
        let err = series
            .write_step(0.0, &small, Some((&found, &geometry)))
            .unwrap_err();
        assert!(err.to_string().contains("not of this system"), "{err}");
        let err = series
            .write_step(0.0, &big, Some((&found, &ContactGeometries::default())))
            .unwrap_err();
        assert_eq!(err.to_string(), "the geometry has 0 rows for 325 contacts");
        assert!(series.is_empty());
        assert!(!dir.join("blocks_000000.vtu").exists());
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn resuming_a_broken_index_is_a_format_error() {
        let dir = scratch("broken");
        fs::create_dir_all(&dir).unwrap();
        assert!(matches!(
            TimeSeries::open(&dir).unwrap_err(),
            IoError::Io { .. }
        ));
        let pvd = |entries: &[PvdEntry]| {
            let mut out = Vec::new();
            write_pvd_to(entries, &mut out).unwrap();
            out
        };
        fs::write(
            dir.join("blocks.pvd"),
            pvd(&[entry(1.0, "a.vtu"), entry(0.0, "b.vtu")]),
        )
        .unwrap();
        let err = TimeSeries::open(&dir).unwrap_err();
        assert!(err.to_string().contains("the times must increase"), "{err}");
        fs::write(dir.join("blocks.pvd"), pvd(&[entry(0.0, "a.vtu")])).unwrap();
        fs::write(dir.join("contacts.pvd"), pvd(&[entry(2.0, "a.vtp")])).unwrap();
        let err = TimeSeries::open(&dir).unwrap_err();
        assert!(err.to_string().contains("after the last blocks"), "{err}");
        fs::remove_dir_all(&dir).unwrap();
    }
}

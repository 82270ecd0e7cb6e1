//! Topographic surfaces read from files: a grid of elevations (XYZ or CSV, ESRI ASCII grid)
//! or a triangulated surface (Wavefront OBJ, binary or ASCII STL); see `docs/generation.md`, "Slopes and
//! topography".
//!
//! The kind of file is told by its extension: `.xyz`, `.csv`, `.txt`, `.dat` and `.asc`
//! are grids; `.obj` and `.stl` are meshes. The readers are small hand parsers of the parts of each
//! format a surface needs; every error says what is wrong and where (line, node, triangle).
//!
//! * **Grid** (`x y z` a line; commas, semicolons, tabs or spaces between; an optional
//!   header line of names; `#` comments): the points must be the nodes of a grid, every
//!   combination of the distinct `x` and the distinct `y` given once (the spacing may
//!   vary). A node without an elevation (a missing line, an empty field, `nan`, `NA`) is a
//!   hole, and an error naming the node. Each cell is cut into two triangles along its
//!   diagonal from its lower-left `(x_i, y_j)` to its upper-right corner.
//! * **ESRI ASCII grid** (`.asc`): the header `ncols`, `nrows`, `xllcorner` or `xllcenter`,
//!   `yllcorner` or `yllcenter`, `cellsize` (or `dx` and `dy`), optional `NODATA_value`,
//!   then the rows, northernmost first. Each value is the elevation at its cell's centre;
//!   a `NODATA_value` is a hole, and an error naming the row, column and point.
//! * **OBJ**: `v x y z` vertices and `f` faces (indices from 1, negative from the end,
//!   `i/t/n` forms); a face of more than three vertices is cut into a fan of triangles from
//!   its first vertex. Other lines (normals, texture coordinates, groups) are ignored.
//! * **STL**: binary (an 80-byte header, a triangle count, 50 bytes a triangle) when the
//!   file's length says so, else ASCII (`solid`, `facet`, `outer loop`, three `vertex`
//!   lines). The facets' normals are ignored.

use super::IoError;
use crate::generation::{Surface, MAX_TRIANGLES};
use std::collections::HashMap;
use std::io::Read;
use std::path::Path;

/// The most bytes of a surface file (1 GiB).
pub const MAX_SURFACE_BYTES: u64 = 1 << 30;

/// Reads a surface file, its kind told by its extension.
///
/// # Errors
///
/// The file cannot be read ([`IoError::Io`]); it is not a surface of its kind, or has a hole
/// in its grid ([`IoError::Syntax`], the message says what and where).
pub fn read_surface(path: &Path) -> Result<Surface, IoError> {
    let syntax = |message: String| IoError::Syntax {
        path: path.to_path_buf(),
        message,
    };
    let kind = Kind::of(path).map_err(syntax)?;
    let failed = |source| IoError::io(path, source);
    let file = std::fs::File::open(path).map_err(failed)?;
    // A path that is not a regular file (a pipe, a device) is read up to the stream limit,
    // so that an endless stream is an error, not a hang.
    let regular = file.metadata().map_err(failed)?.is_file();
    let limit = if regular {
        MAX_SURFACE_BYTES
    } else {
        MAX_SURFACE_BYTES.min(super::MAX_STREAM_BYTES)
    };
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(failed)?;
    if bytes.len() as u64 > limit {
        return Err(syntax(format!(
            "longer than {} MiB: too large for a surface (or an endless stream)",
            limit >> 20
        )));
    }
    let source = path.display().to_string();
    parse_surface(kind, &bytes, &source).map_err(syntax)
}

/// The kinds of surface file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `x y z` points on a grid.
    Grid,
    /// An ESRI ASCII grid (`.asc`).
    Asc,
    /// Wavefront OBJ.
    Obj,
    /// STL, binary or ASCII.
    Stl,
}

impl Kind {
    /// The kind of a file, from its extension.
    pub fn of(path: &Path) -> Result<Kind, String> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "xyz" | "csv" | "txt" | "dat" => Ok(Kind::Grid),
            "asc" => Ok(Kind::Asc),
            "obj" => Ok(Kind::Obj),
            "stl" => Ok(Kind::Stl),
            _ => Err(format!(
                "unknown kind of surface file (extension `.{ext}`): expected .xyz, .csv, .txt \
                 or .dat (a grid of elevations, `x y z` a line), .asc (an ESRI ASCII grid), \
                 .obj or .stl (a triangulated surface)"
            )),
        }
    }
}

/// Parses a surface file's bytes; `source` names it in the surface.
pub fn parse_surface(kind: Kind, bytes: &[u8], source: &str) -> Result<Surface, String> {
    let triangles = match kind {
        Kind::Stl if is_binary_stl(bytes) => binary_stl(bytes)?,
        Kind::Stl => ascii_stl(text(bytes, "an STL file (binary or ASCII)")?)?,
        Kind::Obj => obj(text(bytes, "an OBJ file")?)?,
        Kind::Grid => return grid(text(bytes, "a grid of elevations")?, source),
        Kind::Asc => return asc(text(bytes, "an ESRI ASCII grid")?, source),
    };
    Ok(Surface::new(triangles, source))
}

fn text<'a>(bytes: &'a [u8], what: &str) -> Result<&'a str, String> {
    std::str::from_utf8(bytes).map_err(|e| {
        format!(
            "not {what}: byte {} is not text (UTF-8); a file of another kind?",
            e.valid_up_to()
        )
    })
}

/// A number of a text file, or why not.
fn number(word: &str, line: usize, what: &str) -> Result<f64, String> {
    match word.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!(
            "line {line}: {what} must be a finite number, got `{word}`"
        )),
    }
}

/// Whether a value stands for "no elevation here".
fn is_missing(word: &str) -> bool {
    let w = word.trim().to_ascii_lowercase();
    w.is_empty() || w == "nan" || w == "na" || w == "null" || w == "-nan"
}

/// A grid of `x y z` points.
fn grid(text: &str, source: &str) -> Result<Surface, String> {
    let mut points: Vec<([f64; 2], Option<f64>, usize)> = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let body = raw.split('#').next().unwrap_or("").trim();
        if body.is_empty() {
            continue;
        }
        let words: Vec<&str> = if body.contains([',', ';']) {
            body.split([',', ';']).map(str::trim).collect()
        } else {
            body.split_whitespace().collect()
        };
        let numeric = |w: &str| w.parse::<f64>().is_ok();
        if points.is_empty() && !words.iter().take(2).any(|w| numeric(w)) {
            continue; // a header line of names
        }
        if words.len() != 3 {
            return Err(format!(
                "line {line}: expected three values `x y z`, got {} (`{}`); a grid file has \
                 one node a line",
                words.len(),
                one_line(body)
            ));
        }
        // `+ 0.0` makes -0 the same node as 0.
        let x = number(words[0], line, "x")? + 0.0;
        let y = number(words[1], line, "y")? + 0.0;
        let z = if is_missing(words[2]) {
            None
        } else {
            Some(number(words[2], line, "the elevation z")?)
        };
        points.push(([x, y], z, line));
    }
    if points.is_empty() {
        return Err("no points: not a grid of elevations (`x y z` a line)".into());
    }
    let distinct = |k: usize| {
        let mut v: Vec<f64> = points.iter().map(|p| p.0[k]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let (xs, ys) = (distinct(0), distinct(1));
    if xs.len() < 2 || ys.len() < 2 {
        return Err(format!(
            "the points are not a grid: a grid needs at least 2 distinct x and 2 distinct y, \
             got {} and {}",
            xs.len(),
            ys.len()
        ));
    }
    let nodes = xs.len() * ys.len();
    if nodes > 4 * points.len() {
        return Err(format!(
            "the points are not on a grid ({} points with {} distinct x and {} distinct y): \
             give a grid of elevations, or a triangulated surface (.obj, .stl)",
            points.len(),
            xs.len(),
            ys.len()
        ));
    }
    grid_size(xs.len(), ys.len(), "distinct x by distinct y")?;
    let column: HashMap<u64, usize> = xs
        .iter()
        .enumerate()
        .map(|(i, x)| (x.to_bits(), i))
        .collect();
    let row: HashMap<u64, usize> = ys
        .iter()
        .enumerate()
        .map(|(j, y)| (y.to_bits(), j))
        .collect();
    let mut z = vec![f64::NAN; nodes];
    let mut from = vec![0usize; nodes];
    for (p, value, line) in &points {
        let at = row[&p[1].to_bits()] * xs.len() + column[&p[0].to_bits()];
        if from[at] != 0 {
            return Err(format!(
                "line {line}: the node x = {}, y = {} is given twice (first on line {})",
                p[0], p[1], from[at]
            ));
        }
        from[at] = *line;
        match value {
            Some(v) => z[at] = *v,
            None => {
                return Err(format!(
                    "line {line}: the node x = {}, y = {} has no elevation: a hole in the \
                     surface (every node of the grid needs one)",
                    p[0], p[1]
                ))
            }
        }
    }
    if let Some(at) = from.iter().position(|&l| l == 0) {
        let missing = from.iter().filter(|&&l| l == 0).count();
        return Err(format!(
            "the grid ({} x {} nodes) has no elevation at x = {}, y = {}{}: a hole in the \
             surface (every combination of the distinct x and y needs one)",
            xs.len(),
            ys.len(),
            xs[at % xs.len()],
            ys[at / xs.len()],
            if missing > 1 {
                format!(" and {} other nodes", missing - 1)
            } else {
                String::new()
            }
        ));
    }
    Ok(Surface::from_grid(&xs, &ys, &z, source))
}

/// An ESRI ASCII grid: a header of `key value` lines, then the values row by row from the
/// North.
fn asc(text: &str, source: &str) -> Result<Surface, String> {
    let mut header: HashMap<String, (f64, usize)> = HashMap::new();
    let mut words = text
        .lines()
        .enumerate()
        .flat_map(|(k, l)| l.split_whitespace().map(move |w| (w, k + 1)))
        .peekable();
    while let Some(&(word, line)) = words.peek() {
        if word.parse::<f64>().is_ok() || word.eq_ignore_ascii_case("nan") {
            break;
        }
        words.next();
        let key = word.to_ascii_lowercase();
        let known = [
            "ncols",
            "nrows",
            "xllcorner",
            "yllcorner",
            "xllcenter",
            "yllcenter",
            "cellsize",
            "dx",
            "dy",
            "nodata_value",
        ];
        if !known.contains(&key.as_str()) {
            return Err(format!(
                "line {line}: `{word}` is not a key of an ESRI ASCII grid's header (ncols, \
                 nrows, xllcorner or xllcenter, yllcorner or yllcenter, cellsize or dx and dy, \
                 NODATA_value)"
            ));
        }
        let Some((value, at)) = words.next() else {
            return Err(format!("line {line}: `{word}` has no value"));
        };
        header.insert(key, (number(value, at, word)?, at));
    }
    let get = |keys: &[&'static str]| keys.iter().find_map(|k| header.get(*k).map(|v| (v.0, *k)));
    let need = |keys: &[&'static str]| {
        get(keys).ok_or_else(|| {
            format!(
                "not an ESRI ASCII grid: its header has no `{}`",
                keys.join("` or `")
            )
        })
    };
    let count = |key: &'static str| -> Result<usize, String> {
        let (v, _) = need(&[key])?;
        if v >= 2.0 && v.fract() == 0.0 && v <= 1e8 {
            Ok(v as usize)
        } else {
            Err(format!(
                "`{key}` must be a whole number of at least 2, got {v}"
            ))
        }
    };
    let (ncols, nrows) = (count("ncols")?, count("nrows")?);
    let (dx, dy) = match (get(&["cellsize"]), get(&["dx"]), get(&["dy"])) {
        (Some((c, _)), _, _) => (c, c),
        (None, Some((dx, _)), Some((dy, _))) => (dx, dy),
        _ => return Err("not an ESRI ASCII grid: its header has no `cellsize`".into()),
    };
    if !(dx > 0.0 && dy > 0.0) {
        return Err(format!(
            "the cell size must be greater than zero, got {dx} by {dy}"
        ));
    }
    // The nodes are the cells' centres.
    let centre = |corner: &'static str, center: &'static str, size: f64| -> Result<f64, String> {
        let (v, key) = need(&[corner, center])?;
        Ok(if key == corner { v + size / 2.0 } else { v })
    };
    let x0 = centre("xllcorner", "xllcenter", dx)?;
    let y0 = centre("yllcorner", "yllcenter", dy)?;
    let nodata = get(&["nodata_value"]).map(|v| v.0);
    // Bounded before anything is allocated from the header: the counts alone may claim
    // far more values than the file holds.
    grid_size(ncols, nrows, "ncols x nrows")?;
    // The values as read, row by row from the North: grown as they come, not allocated
    // from the header.
    let mut values: Vec<f64> = Vec::new();
    for row in 0..nrows {
        for col in 0..ncols {
            let Some((word, line)) = words.next() else {
                return Err(format!(
                    "the grid ends after {} of its {} x {} values (ncols x nrows)",
                    row * ncols + col,
                    ncols,
                    nrows
                ));
            };
            let (x, y) = (x0 + col as f64 * dx, y0 + (nrows - 1 - row) as f64 * dy);
            let v = if is_missing(word) {
                None
            } else {
                let v = number(word, line, "an elevation")?;
                (Some(v) != nodata).then_some(v)
            };
            let Some(v) = v else {
                return Err(format!(
                    "line {line}: row {row}, column {col} (x = {x}, y = {y}) has no elevation \
                     (NODATA): a hole in the surface"
                ));
            };
            values.push(v);
        }
    }
    if let Some((word, line)) = words.next() {
        return Err(format!(
            "line {line}: `{word}` is past the grid's {ncols} x {nrows} values"
        ));
    }
    let xs: Vec<f64> = (0..ncols).map(|i| x0 + i as f64 * dx).collect();
    let ys: Vec<f64> = (0..nrows).map(|j| y0 + j as f64 * dy).collect();
    // From the South: row `nrows - 1 - j` of the file is row `j` of the grid.
    let z: Vec<f64> = (0..nrows)
        .rev()
        .flat_map(|row| values[row * ncols..(row + 1) * ncols].iter().copied())
        .collect();
    Ok(Surface::from_grid(&xs, &ys, &z, source))
}

/// A grid of `nx` by `ny` nodes makes `2 (nx - 1) (ny - 1)` triangles: refused (before
/// anything is allocated for it) beyond [`MAX_TRIANGLES`], the limit of every surface.
fn grid_size(nx: usize, ny: usize, what: &str) -> Result<(), String> {
    let triangles = 2 * (nx as u128).saturating_sub(1) * (ny as u128).saturating_sub(1);
    if triangles > MAX_TRIANGLES as u128 {
        return Err(format!(
            "a grid of {nx} x {ny} nodes ({what}) would make {triangles} triangles, more than \
             the limit of {MAX_TRIANGLES} of a surface"
        ));
    }
    Ok(())
}

/// The triangles of a mesh so far, refused beyond [`MAX_TRIANGLES`] as they are read.
fn mesh_size(triangles: usize) -> Result<(), String> {
    if triangles > MAX_TRIANGLES {
        return Err(format!(
            "more than {MAX_TRIANGLES} triangles, the limit of a surface"
        ));
    }
    Ok(())
}

fn one_line(text: &str) -> String {
    match text.char_indices().nth(60) {
        Some((cut, _)) => format!("{}...", &text[..cut]),
        None => text.to_string(),
    }
}

/// The triangles of an OBJ file.
fn obj(text: &str) -> Result<Vec<[[f64; 3]; 3]>, String> {
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut triangles = Vec::new();
    let mut faces = 0usize;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let body = raw.split('#').next().unwrap_or("").trim();
        let mut words = body.split_whitespace();
        match words.next() {
            Some("v") => {
                let coords: Vec<&str> = words.collect();
                if coords.len() < 3 {
                    return Err(format!("line {line}: a vertex needs x, y and z"));
                }
                let mut p = [0.0; 3];
                for (c, w) in p.iter_mut().zip(&coords) {
                    *c = number(w, line, "a vertex coordinate")?;
                }
                vertices.push(p);
            }
            Some("f") => {
                faces += 1;
                let corners = words
                    .map(|w| {
                        let index = w.split('/').next().unwrap_or("");
                        let i: i64 = index
                            .parse()
                            .map_err(|_| format!("line {line}: `{w}` is not a vertex index"))?;
                        let n = vertices.len() as i64;
                        let at = if i > 0 { i - 1 } else { n + i };
                        if i == 0 || at < 0 || at >= n {
                            return Err(format!(
                                "line {line}: vertex index {i} is out of range (1 to {n}, or \
                                 -1 to -{n}, the vertices defined so far)"
                            ));
                        }
                        Ok(vertices[at as usize])
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                if corners.len() < 3 {
                    return Err(format!("line {line}: a face needs at least 3 vertices"));
                }
                mesh_size(triangles.len() + corners.len() - 2)
                    .map_err(|why| format!("line {line}: {why}"))?;
                for c in 1..corners.len() - 1 {
                    triangles.push([corners[0], corners[c], corners[c + 1]]);
                }
            }
            _ => {}
        }
    }
    if faces == 0 {
        return Err(format!(
            "no faces (`f` lines; {} vertices): not a triangulated surface",
            vertices.len()
        ));
    }
    Ok(triangles)
}

/// Whether STL bytes are binary: the length is that of the triangle count they declare.
fn is_binary_stl(bytes: &[u8]) -> bool {
    bytes.len() >= 84 && {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        bytes.len() as u64 == 84 + 50 * n
    }
}

fn binary_stl(bytes: &[u8]) -> Result<Vec<[[f64; 3]; 3]>, String> {
    let n = (bytes.len() - 84) / 50;
    let float = |at: usize| {
        f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]) as f64
    };
    mesh_size(n)?;
    let mut triangles = Vec::with_capacity(n);
    for t in 0..n {
        let base = 84 + 50 * t + 12; // past the normal
        let p = |c: usize| [0, 1, 2].map(|k| float(base + 12 * c + 4 * k));
        triangles.push([p(0), p(1), p(2)]);
    }
    if n == 0 {
        return Err("a binary STL file of no triangles".into());
    }
    Ok(triangles)
}

fn ascii_stl(text: &str) -> Result<Vec<[[f64; 3]; 3]>, String> {
    let first = text.split_whitespace().next().unwrap_or("");
    if first != "solid" {
        return Err(format!(
            "not an STL file: an ASCII STL starts with `solid`, and the length ({} bytes) is \
             not that of a binary STL (84 + 50 per triangle)",
            text.len()
        ));
    }
    let mut triangles = Vec::new();
    let mut corners: Vec<[f64; 3]> = Vec::with_capacity(3);
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let mut words = raw.split_whitespace();
        match words.next() {
            Some("vertex") => {
                let coords: Vec<&str> = words.collect();
                if coords.len() != 3 {
                    return Err(format!("line {line}: a vertex needs x, y and z"));
                }
                let mut p = [0.0; 3];
                for (c, w) in p.iter_mut().zip(&coords) {
                    *c = number(w, line, "a vertex coordinate")?;
                }
                corners.push(p);
            }
            Some("endloop") => {
                if corners.len() != 3 {
                    return Err(format!(
                        "line {line}: a facet has {} vertices, not 3",
                        corners.len()
                    ));
                }
                mesh_size(triangles.len() + 1).map_err(|why| format!("line {line}: {why}"))?;
                triangles.push([corners[0], corners[1], corners[2]]);
                corners.clear();
            }
            _ => {}
        }
    }
    if triangles.is_empty() {
        return Err("an STL file with no facets".into());
    }
    Ok(triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_with_a_header_and_commas_is_read_in_any_order() {
        let text = "x,y,z\n1,0,5\n0,0,4\n0,2,6\n1,2,7\n";
        let s = parse_surface(Kind::Grid, text.as_bytes(), "g.csv").unwrap();
        assert_eq!(s.triangles.len(), 2);
        assert_eq!(
            s.triangles[0],
            [[0.0, 0.0, 4.0], [1.0, 0.0, 5.0], [1.0, 2.0, 7.0]]
        );
        assert_eq!(s.source, "g.csv");
    }

    #[test]
    fn a_grid_with_a_hole_or_a_twice_given_node_is_an_error_naming_the_node() {
        let hole = "0 0 1\n1 0 1\n0 1 1\n2 0 1\n2 1 1\n";
        let e = parse_surface(Kind::Grid, hole.as_bytes(), "g").unwrap_err();
        assert!(e.contains("no elevation at x = 1, y = 1"), "{e}");
        let nan = "0 0 1\n1 0 1\n0 1 nan\n1 1 1\n";
        let e = parse_surface(Kind::Grid, nan.as_bytes(), "g").unwrap_err();
        assert!(
            e.contains("line 3: the node x = 0, y = 1 has no elevation"),
            "{e}"
        );
        let twice = "0 0 1\n1 0 1\n0 1 1\n1 1 1\n0 0 2\n";
        let e = parse_surface(Kind::Grid, twice.as_bytes(), "g").unwrap_err();
        assert!(
            e.contains("line 5: the node x = 0, y = 0 is given twice"),
            "{e}"
        );
        let words = "0 0 1\n1 0 one\n";
        let e = parse_surface(Kind::Grid, words.as_bytes(), "g").unwrap_err();
        assert!(
            e.contains("line 2: the elevation z must be a finite number"),
            "{e}"
        );
    }

    #[test]
    fn any_bytes_give_a_surface_or_an_error_never_a_panic() {
        // SplitMix64 bytes, and mutations of valid files.
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        let seeds: [&[u8]; 3] = [
            b"x,y,z\n0,0,1\n1,0,2\n0,1,-0\n1,1,3\n",
            b"v 0 0 0\nv 1 0 0\nv 0 1 1\nf 1 2 3\nf -1 -2 -3\n",
            b"solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
              vertex 0 1 0\nendloop\nendfacet\nendsolid\n",
        ];
        for round in 0..3000 {
            let mut bytes = seeds[round % 3].to_vec();
            for _ in 0..(next() % 6) {
                let at = (next() as usize) % bytes.len();
                bytes[at] = b"0123456789 -,.\nvfe/#nai"[(next() as usize) % 23];
            }
            if round % 10 == 0 {
                bytes = (0..next() % 200).map(|_| next() as u8).collect();
            }
            for kind in [Kind::Grid, Kind::Asc, Kind::Obj, Kind::Stl] {
                let _ = parse_surface(kind, &bytes, "fuzz");
            }
        }
        // -0 and 0 are one node.
        let s = parse_surface(Kind::Grid, seeds[0], "g").unwrap();
        assert_eq!(s.triangles.len(), 2);
    }

    #[test]
    fn an_esri_grid_is_read_from_the_north_and_its_nodata_is_a_hole() {
        let text = "ncols 3\nnrows 2\nxllcorner 10\nyllcorner 20\ncellsize 2\n\
                    NODATA_value -9999\n1 2 3\n4 5 6\n";
        let s = parse_surface(Kind::Asc, text.as_bytes(), "g.asc").unwrap();
        // Centres x = 11, 13, 15 and y = 21 (the second row), 23 (the first).
        assert_eq!(s.triangles.len(), 4);
        assert_eq!(
            s.triangles[0],
            [[11.0, 21.0, 4.0], [13.0, 21.0, 5.0], [13.0, 23.0, 2.0]]
        );
        let hole = text.replace("5 6", "-9999 6");
        let e = parse_surface(Kind::Asc, hole.as_bytes(), "g.asc").unwrap_err();
        assert!(
            e.contains("row 1, column 1 (x = 13, y = 21) has no elevation"),
            "{e}"
        );
        let short = text.replace("4 5 6\n", "4 5\n");
        let e = parse_surface(Kind::Asc, short.as_bytes(), "g.asc").unwrap_err();
        assert!(e.contains("ends after 5 of its 3 x 2 values"), "{e}");
        let e = parse_surface(Kind::Asc, b"v 0 0 0\nf 1 1 1\n", "x.asc").unwrap_err();
        assert!(e.contains("`v` is not a key"), "{e}");
        let centred = text.replace("llcorner", "llcenter");
        let s = parse_surface(Kind::Asc, centred.as_bytes(), "g.asc").unwrap();
        assert_eq!(s.triangles[0][0], [10.0, 20.0, 4.0]);
    }

    #[test]
    fn an_esri_header_beyond_the_triangle_limit_is_refused_before_its_values_are_read() {
        // The counts alone claim 10^16 values (80 PB): refused, not allocated.
        let e = parse_surface(
            Kind::Asc,
            b"ncols 100000000\nnrows 100000000\nxllcorner 0\nyllcorner 0\ncellsize 1\n5 5 5\n",
            "huge.asc",
        )
        .unwrap_err();
        assert!(
            e.contains(&format!("more than the limit of {MAX_TRIANGLES}")),
            "{e}"
        );
        // Just past the limit (1001 x 1002 nodes: 2 (nx - 1) (ny - 1) triangles), with one
        // value; 1001 x 1001 nodes are exactly at it.
        assert_eq!(2 * 1000 * 1000, MAX_TRIANGLES);
        let e = parse_surface(
            Kind::Asc,
            b"ncols 1001\nnrows 1002\nxllcorner 0\nyllcorner 0\ncellsize 1\n5\n",
            "big.asc",
        )
        .unwrap_err();
        let triangles = 2 * (1001 - 1) * (1002 - 1);
        assert!(
            e.contains(&format!("would make {triangles} triangles")),
            "{e}"
        );
        // At the limit, a file that ends early is told so.
        let e = parse_surface(
            Kind::Asc,
            b"ncols 1001\nnrows 1001\nxllcorner 0\nyllcorner 0\ncellsize 1\n5\n",
            "short.asc",
        )
        .unwrap_err();
        assert!(e.contains("ends after 1 of its 1001 x 1001 values"), "{e}");
    }

    #[test]
    fn a_mesh_beyond_the_triangle_limit_is_refused_as_it_is_read() {
        // One face of MAX_TRIANGLES + 3 vertices: MAX_TRIANGLES + 1 triangles of its fan.
        let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
        for k in 0..MAX_TRIANGLES + 3 {
            text += [" 1", " 2", " 3"][k % 3];
        }
        let e = parse_surface(Kind::Obj, text.as_bytes(), "big.obj").unwrap_err();
        assert!(e.contains("line 4: more than 2000000 triangles"), "{e}");
    }

    #[test]
    fn obj_faces_are_fanned_and_indices_may_be_negative() {
        let text = "# a square\nv 0 0 1\nv 1 0 1\nv 1 1 2\nv 0 1 2\nvn 0 0 1\nf 1/1/1 2//1 3 4\n\
                    f -4 -2 -1\n";
        let t = obj(text).unwrap();
        assert_eq!(t.len(), 3);
        assert_eq!(t[1], [[0.0, 0.0, 1.0], [1.0, 1.0, 2.0], [0.0, 1.0, 2.0]]);
        assert!(obj("v 0 0 0\nf 1 2 3\n")
            .unwrap_err()
            .contains("out of range"));
        assert!(obj("v 0 0 0\n").unwrap_err().contains("no faces"));
    }

    #[test]
    fn binary_and_ascii_stl_give_the_same_triangle() {
        let tri = [[0.0, 0.0, 1.0], [2.0, 0.0, 1.5], [0.0, 3.0, 0.5]];
        let mut bin = vec![0u8; 80];
        bin.extend(1u32.to_le_bytes());
        bin.extend([0u8; 12]);
        for p in tri {
            for c in p {
                bin.extend((c as f32).to_le_bytes());
            }
        }
        bin.extend([0u8; 2]);
        let a = parse_surface(Kind::Stl, &bin, "b.stl").unwrap();
        let ascii = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 1\nvertex 2 0 1.5\n\
                     vertex 0 3 0.5\nendloop\nendfacet\nendsolid s\n";
        let b = parse_surface(Kind::Stl, ascii.as_bytes(), "a.stl").unwrap();
        assert_eq!(a.triangles, vec![tri]);
        assert_eq!(b.triangles, vec![tri]);
        // An OBJ given as STL, and a PNG-like binary, say what they are not.
        let e = parse_surface(Kind::Stl, b"v 0 0 0\nf 1 1 1\n", "x.stl").unwrap_err();
        assert!(e.contains("not an STL file"), "{e}");
        let e = parse_surface(Kind::Obj, &[0x89, b'P', b'N', b'G', 0xff], "x.obj").unwrap_err();
        assert!(e.contains("not an OBJ file"), "{e}");
        assert!(Kind::of(Path::new("a.png")).unwrap_err().contains("`.png`"));
    }
}

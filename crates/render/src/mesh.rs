//! Wavefront OBJ loading: vertices and faces (polygons fanned into
//! triangles). Normals, texture coordinates and groups are ignored.

use glam::DVec3;

/// A line of an OBJ file that cannot be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct MeshError {
    /// 1-based line.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Reads the triangles of an OBJ text. Errors name the line.
pub fn parse_obj(text: &str) -> Result<Vec<[DVec3; 3]>, MeshError> {
    let mut verts = Vec::new();
    let mut tris = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let err = |message: String| MeshError { line: k + 1, message };
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it
                    .take(3)
                    .map(|s| s.parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| err("a vertex needs 3 numbers".into()))?;
                if c.len() != 3 || !c.iter().all(|x| x.is_finite()) {
                    return Err(err("a vertex needs 3 finite numbers".into()));
                }
                verts.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("f") => {
                let idx: Vec<usize> = it
                    .map(|s| {
                        let first = s.split('/').next().unwrap_or("");
                        let i: i64 = first.parse().map_err(|_| err(format!("bad face index \"{s}\"")))?;
                        // 1-based; negative counts from the end
                        let j = if i > 0 { i - 1 } else { verts.len() as i64 + i };
                        if j < 0 || j as usize >= verts.len() {
                            return Err(err(format!("face index {i} does not name a vertex")));
                        }
                        Ok(j as usize)
                    })
                    .collect::<Result<_, _>>()?;
                if idx.len() < 3 {
                    return Err(err("a face needs at least 3 vertices".into()));
                }
                for w in 1..idx.len() - 1 {
                    tris.push([verts[idx[0]], verts[idx[w]], verts[idx[w + 1]]]);
                }
            }
            _ => {}
        }
    }
    if tris.is_empty() {
        return Err(MeshError {
            line: text.lines().count().max(1),
            message: "the file has no faces (f lines): it draws nothing".into(),
        });
    }
    Ok(tris)
}

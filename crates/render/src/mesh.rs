//! Wavefront OBJ loading: vertices and faces (polygons fanned into
//! triangles). Normals, texture coordinates and groups are ignored.

use glam::DVec3;

/// Reads the triangles of an OBJ text. Errors name the line.
pub fn parse_obj(text: &str) -> Result<Vec<[DVec3; 3]>, String> {
    let mut verts = Vec::new();
    let mut tris = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f64> = it
                    .take(3)
                    .map(|s| s.parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| format!("line {}: a vertex needs 3 numbers", k + 1))?;
                if c.len() != 3 || !c.iter().all(|x| x.is_finite()) {
                    return Err(format!("line {}: a vertex needs 3 finite numbers", k + 1));
                }
                verts.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("f") => {
                let idx: Vec<usize> = it
                    .map(|s| {
                        let first = s.split('/').next().unwrap_or("");
                        let i: i64 = first.parse().map_err(|_| format!("line {}: bad face index \"{s}\"", k + 1))?;
                        // 1-based; negative counts from the end
                        let j = if i > 0 { i - 1 } else { verts.len() as i64 + i };
                        if j < 0 || j as usize >= verts.len() {
                            return Err(format!("line {}: face index {i} does not name a vertex", k + 1));
                        }
                        Ok(j as usize)
                    })
                    .collect::<Result<_, _>>()?;
                if idx.len() < 3 {
                    return Err(format!("line {}: a face needs at least 3 vertices", k + 1));
                }
                for w in 1..idx.len() - 1 {
                    tris.push([verts[idx[0]], verts[idx[w]], verts[idx[w + 1]]]);
                }
            }
            _ => {}
        }
    }
    Ok(tris)
}

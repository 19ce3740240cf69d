//! Media as GPU records: the medium record, its density grid and its majorant grid
//! (what `render::scene_buffers` uploads).

use glam::{Mat4, Vec3};

use super::{Grid, Medium, MediumKind};
use crate::gpu::layout::{
    MediumRecord, MEDIUM_ALBEDO_RGB, MEDIUM_DENSITY_PACKED, MEDIUM_GRID, MEDIUM_HOMOGENEOUS,
    MEDIUM_SAMPLE_EMITTERS, NONE,
};

/// Relative headroom of majorants over the largest extinction they bound, so that f32
/// rounding of the trilinear interpolation can never exceed them.
const MAJORANT_HEADROOM: f32 = 1.0 + 1e-5;

/// Most voxels a density grid may have to be packed (`pack_density`): 16 MiB voxels,
/// 256 MiB of texels. Larger grids stay in the grid buffer, four bytes a value.
pub const PACKED_DENSITY_MAX_VOXELS: usize = 1 << 24;

/// The record of medium `m`; a grid medium appends its density grid to `packed`
/// (`pack_density`) or, too large for that, to `grid_data`, its albedo grid to
/// `grid_data` and its majorant grid to `majorants`.
pub fn record(
    m: &Medium,
    grid_data: &mut Vec<f32>,
    packed: &mut Vec<[f32; 4]>,
    majorants: &mut Vec<f32>,
) -> MediumRecord {
    let mut rec = MediumRecord {
        albedo: m.albedo.into(),
        g: m.g,
        flags: if m.sample_emitters {
            MEDIUM_SAMPLE_EMITTERS
        } else {
            0
        },
        world_to_grid: Mat4::IDENTITY.to_cols_array_2d(),
        res: [1, 1, 1],
        maj_res: [1, 1, 1],
        channels: 1,
        albedo_data: NONE,
        ..Default::default()
    };
    if let Some(a) = &m.albedo_grid {
        rec.albedo_data = grid_data.len() as u32;
        grid_data.extend(albedo_grid_header(a));
        grid_data.extend_from_slice(&a.data);
        if a.channels == 3 {
            rec.flags |= MEDIUM_ALBEDO_RGB;
        }
        // The albedo is the grid's: the record's constant must not read as a pure
        // absorber (medium.glsl takes albedo 0 as one).
        rec.albedo = [1.0; 3];
    }
    match &m.kind {
        MediumKind::Homogeneous { sigma_t } => {
            rec.kind = MEDIUM_HOMOGENEOUS;
            rec.sigma_t = (*sigma_t).into();
            rec.majorant = sigma_t.max_element();
        }
        MediumKind::Grid {
            grid,
            scale,
            majorant_factor,
        } => {
            rec.kind = MEDIUM_GRID;
            rec.sigma_t = (*scale).into();
            rec.world_to_grid = grid.to_world.inverse().to_cols_array_2d();
            rec.res = grid.res;
            rec.channels = grid.channels;
            match pack_density(grid) {
                Some(texels) => {
                    rec.flags |= MEDIUM_DENSITY_PACKED;
                    rec.data = packed.len() as u32;
                    packed.extend(texels);
                }
                None => {
                    rec.data = grid_data.len() as u32;
                    grid_data.extend_from_slice(&grid.data);
                }
            }
            let (maj_res, maj) = majorant_grid(grid, *scale, *majorant_factor);
            rec.maj_res = maj_res;
            rec.maj_data = majorants.len() as u32;
            rec.majorant = maj.iter().fold(0.0f32, |a, &b| a.max(b));
            majorants.extend(maj);
        }
    }
    rec
}

/// Words of an albedo grid's header in the grid buffer ([`albedo_grid_header`]).
pub const ALBEDO_GRID_HEADER: usize = 16;

/// The header that precedes an albedo grid's values in the grid buffer (medium.glsl
/// `medium_albedo`): its world-to-grid map as three rows of four (the unit cube its
/// `to_world` places), its resolution (three u32 bit patterns) and channel count. An
/// albedo grid is looked up in its own grid, as Mitsuba does, whatever the density's.
pub fn albedo_grid_header(a: &Grid) -> [f32; ALBEDO_GRID_HEADER] {
    let m = a.to_world.inverse().transpose().to_cols_array();
    let mut h = [0.0; ALBEDO_GRID_HEADER];
    // The transpose's columns are the map's rows; the fourth row (0, 0, 0, 1) is left.
    h[..12].copy_from_slice(&m[..12]);
    for (k, r) in a.res.iter().enumerate() {
        h[12 + k] = f32::from_bits(*r);
    }
    h[15] = f32::from_bits(a.channels);
    h
}

/// The density grid as one 16-byte texel per voxel, so that a trilinear lookup
/// fetches 2 texels (one channel) or 8 (three) instead of 8 or 24 single values: a
/// texel load costs about the same for one value as for four, on llvmpipe (a gather
/// of the lanes' addresses) as on GPUs (a memory transaction). One channel: voxel (x, y, z) holds the
/// values at (x, y), (x+1, y), (x, y+1) and (x+1, y+1) of slice z, clamped to the grid
/// as the lookup clamps; three channels: its RGB and a 0. `None` for grids of more than
/// [`PACKED_DENSITY_MAX_VOXELS`] voxels (or another channel count), which the lookup
/// reads value by value.
pub fn pack_density(grid: &Grid) -> Option<Vec<[f32; 4]>> {
    let [rx, ry, rz] = grid.res.map(|r| r as usize);
    let voxels = rx * ry * rz;
    if voxels > PACKED_DENSITY_MAX_VOXELS || voxels == 0 {
        return None;
    }
    let d = &grid.data;
    match grid.channels {
        1 => {
            let at = |x: usize, y: usize, z: usize| d[(z * ry + y) * rx + x];
            let mut out = Vec::with_capacity(voxels);
            for z in 0..rz {
                for y in 0..ry {
                    let y1 = (y + 1).min(ry - 1);
                    for x in 0..rx {
                        let x1 = (x + 1).min(rx - 1);
                        out.push([at(x, y, z), at(x1, y, z), at(x, y1, z), at(x1, y1, z)]);
                    }
                }
            }
            Some(out)
        }
        3 => Some(d.chunks_exact(3).map(|c| [c[0], c[1], c[2], 0.0]).collect()),
        _ => None,
    }
}

/// A coarse grid of cells over the grid's unit cube, each holding an upper bound of
/// the extinction (max over channels of scale x density) at every point inside it:
/// the maximum over every voxel whose value the trilinear interpolation (between voxel
/// centres, clamped at the edges) can reach from the cell. `factor` voxels per cell
/// along each axis; 0 for one cell. Returns (cells per axis, values in x-fastest order).
pub fn majorant_grid(grid: &Grid, scale: Vec3, factor: u32) -> ([u32; 3], Vec<f32>) {
    let res = grid.res;
    let cells = if factor == 0 {
        [1, 1, 1]
    } else {
        res.map(|r| r.div_ceil(factor).max(1))
    };
    // Voxels interpolated from a cell [c/M, (c+1)/M) along one axis: the voxel
    // coordinate x = p r - 1/2 spans [c r/M - 1/2, (c+1) r/M - 1/2]; voxels floor(lo)
    // to floor(hi) + 1, clamped.
    let span = |c: u32, m: u32, r: u32| {
        let lo = (c as f64 * r as f64 / m as f64 - 0.5).floor() as i64;
        let hi = ((c + 1) as f64 * r as f64 / m as f64 - 0.5).floor() as i64 + 1;
        (
            lo.clamp(0, r as i64 - 1) as usize,
            hi.clamp(0, r as i64 - 1) as usize,
        )
    };
    let ch = grid.channels as usize;
    let scale = scale.to_array();
    let mut out = Vec::with_capacity((cells[0] * cells[1] * cells[2]) as usize);
    for cz in 0..cells[2] {
        let (z0, z1) = span(cz, cells[2], res[2]);
        for cy in 0..cells[1] {
            let (y0, y1) = span(cy, cells[1], res[1]);
            for cx in 0..cells[0] {
                let (x0, x1) = span(cx, cells[0], res[0]);
                let mut m = 0.0f32;
                for z in z0..=z1 {
                    for y in y0..=y1 {
                        let row = (z * res[1] as usize + y) * res[0] as usize;
                        for x in x0..=x1 {
                            for (c, s) in scale.iter().enumerate().take(3) {
                                let v = grid.data[(row + x) * ch + c.min(ch - 1)];
                                m = m.max(v * s);
                            }
                        }
                    }
                }
                out.push(m * MAJORANT_HEADROOM);
            }
        }
    }
    (cells, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trilinear(g: &Grid, p: Vec3) -> f32 {
        let r = Vec3::new(g.res[0] as f32, g.res[1] as f32, g.res[2] as f32);
        let x = p * r - 0.5;
        let f = x.floor();
        let w = x - f;
        let mut v = 0.0;
        for k in 0..8 {
            let o = Vec3::new((k & 1) as f32, ((k >> 1) & 1) as f32, ((k >> 2) & 1) as f32);
            let i = (f + o).clamp(Vec3::ZERO, r - 1.0);
            let wt = Vec3::select(o.cmpgt(Vec3::ZERO), w, 1.0 - w);
            let idx = ((i.z as u32 * g.res[1] + i.y as u32) * g.res[0] + i.x as u32) as usize;
            v += wt.x * wt.y * wt.z * g.data[idx];
        }
        v
    }

    /// Every interpolated density lies under its cell's majorant, for spiky grids and
    /// resolutions that the factor does not divide.
    #[test]
    fn majorants_bound_the_interpolated_density() {
        let res = [13u32, 7, 9];
        let n = (res[0] * res[1] * res[2]) as usize;
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut rand = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        // Random values and spikes, and an empty slab x < 5.
        let data: Vec<f32> = (0..n)
            .map(|i| {
                let u = rand();
                if u < 0.6 || i % res[0] as usize <= 4 {
                    0.0
                } else if u < 0.97 {
                    u as f32
                } else {
                    1000.0
                }
            })
            .collect();
        let grid = Grid {
            res,
            channels: 1,
            data,
            to_world: Mat4::IDENTITY,
        };
        for factor in [0u32, 1, 2, 4, 8] {
            let (cells, maj) = majorant_grid(&grid, Vec3::splat(2.0), factor);
            let mut zero_cells = 0;
            for _ in 0..20000 {
                let p = Vec3::new(rand() as f32, rand() as f32, rand() as f32);
                let c = [0, 1, 2].map(|a| ((p[a] * cells[a] as f32) as u32).min(cells[a] - 1));
                let m = maj[((c[2] * cells[1] + c[1]) * cells[0] + c[0]) as usize];
                let v = 2.0 * trilinear(&grid, p);
                assert!(
                    v <= m,
                    "factor {factor}: density {v} above majorant {m} at {p}"
                );
                zero_cells += (m == 0.0) as u32;
            }
            if factor == 1 {
                // Fine majorants are tight: sparse regions get empty cells.
                assert!(zero_cells > 0);
            }
        }
    }
}

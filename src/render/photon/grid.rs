//! The photon hash grid, built on the GPU by a counting sort (`photon_grid_count`,
//! `photon_grid_scan`, `photon_grid_place` in `shaders/kernels/`; the lookups in
//! `shaders/photon/grid.glsl`).
//!
//! Space is cut into cubes of side `cell` (at least twice the largest gather radius, so
//! that the photons within r of a point lie in the 2 x 2 x 2 cells around it), each
//! hashed into one of a power of two of buckets. The sort counts the photons of each
//! bucket (atomic adds of integers, whose result does not depend on their order), turns
//! the counts into prefix sums, and places each photon below its bucket's end with an
//! atomic decrement: bucket `b` then holds grid photons `cells[b] .. cells[b + 1]`. No
//! linked lists and no float atomics. Photons of a bucket come in no particular order,
//! so a gather's float sum may differ between runs in its last bits; which photons a
//! gather finds does not.

use crate::gpu::layout::{Push, WORKGROUP_SIZE};
use crate::gpu::{
    shaders, BindingLayout, CommandList, DescriptorSet, Device, Kernel, KernelSpec, Spec,
    SpecValues,
};

use super::super::error::Result;
use super::super::groups_for;
use super::PhotonMap;

/// Buckets one workgroup of `photon_grid_scan` sums (`SCAN_BLOCK`).
pub const SCAN_BLOCK: u32 = WORKGROUP_SIZE * 8;

/// Fewest buckets a grid has (one scan block).
pub const MIN_BUCKETS: u32 = SCAN_BLOCK;

/// Most buckets a grid may have: the scan's single second-stage workgroup and a 2D
/// dispatch stay small, and the bucket array fits one binding of every device here.
pub const MAX_BUCKETS: u32 = 1 << 24;

/// How much longer a cell is than twice the largest gather radius: the gather's cube
/// reaches 1e-5 past its radius (`grid_cell_range` in grid.glsl), and must still meet
/// at most 2 cells per axis. Cells of the radius itself (up to 27 of them, 27 r³
/// searched instead of 64 r³) were measured no faster on lavapipe: the gathers' time
/// goes to the photons within the radius (their BSDF), and each cell costs a hash,
/// two loads and a check against the others.
const CELL_MARGIN: f32 = 1.0 + 1e-4;

/// Most cells from the origin to the farthest point of the scene along an axis: cell
/// coordinates stay far inside an `int`, and cells are not smaller than the scene's
/// coordinates can resolve.
const MAX_CELLS_FROM_ORIGIN: f32 = (1 << 20) as f32;

/// The cells and buckets of one grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridShape {
    pub cell: f32,
    /// Buckets, a power of two.
    pub buckets: u32,
}

impl GridShape {
    /// The grid for `photons` photons gathered within at most `max_radius`, in a scene
    /// whose coordinates reach `max_abs_coord` from the origin, with at most
    /// `max_buckets` buckets: twice as many buckets as photons (a bucket holds about
    /// one cell's photons), cells a hair longer than twice the radius, and no smaller
    /// than `max_abs_coord` / 2^20 (see [`MAX_CELLS_FROM_ORIGIN`]).
    pub fn new(photons: u32, max_radius: f32, max_abs_coord: f32, max_buckets: u32) -> GridShape {
        let floor = if max_abs_coord.is_finite() {
            max_abs_coord / MAX_CELLS_FROM_ORIGIN
        } else {
            0.0
        };
        let cell = (2.0 * max_radius * CELL_MARGIN)
            .max(floor)
            .max(f32::MIN_POSITIVE);
        let buckets = (2 * photons as u64)
            .next_power_of_two()
            .clamp(MIN_BUCKETS as u64, max_buckets.max(MIN_BUCKETS) as u64)
            as u32;
        GridShape { cell, buckets }
    }

    /// Block sums the scan needs: one per scan block, padded to whole blocks.
    pub fn scan_sums(buckets: u32) -> u32 {
        (buckets / SCAN_BLOCK).next_multiple_of(SCAN_BLOCK)
    }
}

/// The kernels of the grid build.
pub struct GridKernels {
    count: Kernel,
    scan: [Kernel; 3],
    place: Kernel,
}

impl GridKernels {
    /// The grid's kernels on their own (the photon mapper creates them with its others:
    /// [`GridKernels::specs`]).
    pub fn new(device: &Device, layout: &BindingLayout) -> Result<GridKernels> {
        let mut made = Kernel::new_all(device, layout, &Self::specs())?.into_iter();
        Ok(Self::take(|| {
            made.next()
                .unwrap_or_else(|| unreachable!("one kernel per spec"))
        }))
    }

    /// The grid's kernels, to create with the photon mapper's others
    /// (Kernel::new_all); [`GridKernels::take`] takes them back in this order.
    pub fn specs() -> [KernelSpec<'static>; 5] {
        let scan = |level: u32| {
            let stage = SpecValues::new().with(Spec::ScanStage, level);
            KernelSpec::named("photon_grid_scan", shaders::PHOTON_GRID_SCAN, &stage)
        };
        [
            KernelSpec::new("photon_grid_count", shaders::PHOTON_GRID_COUNT, &[]),
            scan(0),
            scan(1),
            scan(2),
            KernelSpec::new("photon_grid_place", shaders::PHOTON_GRID_PLACE, &[]),
        ]
    }

    /// The kernels made from [`GridKernels::specs`], taken in order from `next`.
    pub fn take(mut next: impl FnMut() -> Kernel) -> GridKernels {
        GridKernels {
            count: next(),
            scan: [next(), next(), next()],
            place: next(),
        }
    }

    /// Every kernel, for the warm-up dispatch.
    pub fn all(&self) -> Vec<&Kernel> {
        let mut v = vec![&self.count, &self.place];
        v.extend(self.scan.iter());
        v
    }

    /// Records the build of the grid of photons `0 .. photons` of `map` with
    /// `buckets` buckets (a power of two, at least [`MIN_BUCKETS`]). The cell size,
    /// bucket mask and path limit come from the map's parameters, which the caller has
    /// written. Uses only descriptor set 2 (`set`).
    pub fn record(
        &self,
        cmd: &mut CommandList,
        map: &PhotonMap,
        set: &DescriptorSet,
        photons: u32,
        buckets: u32,
    ) {
        debug_assert!(buckets.is_power_of_two() && buckets >= MIN_BUCKETS);
        let sets = [set];
        cmd.fill(&map.store.cells, 0, (buckets as u64 + 1) * 4, 0);
        let sums = GridShape::scan_sums(buckets) as u64 * 4;
        cmd.fill(&map.store.scan_sums, 0, sums, 0);
        cmd.barrier();
        let over = |n: u32| Push {
            path_count: n,
            ..Default::default()
        };
        let photons_push = over(photons);
        let p = bytemuck::bytes_of(&photons_push);
        if photons > 0 {
            cmd.dispatch(&self.count, &sets, p, groups_for(photons));
            cmd.barrier();
        }
        let buckets_push = over(buckets);
        let b = bytemuck::bytes_of(&buckets_push);
        let blocks = buckets / SCAN_BLOCK;
        cmd.dispatch(&self.scan[0], &sets, b, [blocks, 1, 1]);
        cmd.barrier();
        cmd.dispatch(&self.scan[1], &sets, b, [1, 1, 1]);
        cmd.barrier();
        cmd.dispatch(&self.scan[2], &sets, b, [blocks, 1, 1]);
        cmd.barrier();
        if photons > 0 {
            cmd.dispatch(&self.place, &sets, p, groups_for(photons));
            cmd.barrier();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_hold_the_radius_with_a_margin_and_buckets_are_powers_of_two() {
        let g = GridShape::new(1000, 0.5, 10.0, MAX_BUCKETS);
        assert!(g.cell > 1.0 && g.cell < 1.001, "{g:?}");
        assert_eq!(g.buckets, 2048);
        // Few photons: one scan block; many: capped.
        assert_eq!(
            GridShape::new(3, 0.5, 10.0, MAX_BUCKETS).buckets,
            MIN_BUCKETS
        );
        assert_eq!(
            GridShape::new(u32::MAX / 2, 0.5, 10.0, 1 << 20).buckets,
            1 << 20
        );
        // A radius far below the precision of the scene's coordinates: cells of at
        // least max_abs_coord / 2^20.
        let g = GridShape::new(1000, 1e-6, 1e4, MAX_BUCKETS);
        assert!(g.cell >= 1e4 / 1048576.0, "{g:?}");
        assert_eq!(GridShape::scan_sums(1 << 20), 1024);
        assert_eq!(GridShape::scan_sums(1 << 24), 16384);
        assert_eq!(GridShape::scan_sums(SCAN_BLOCK), SCAN_BLOCK);
    }
}

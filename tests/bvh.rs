//! The GLSL BVH traversal against the CPU: closest hits equal a brute-force search,
//! any-hit agrees, and so does the second-nearest hit of `bvh_closest_two`, on a real
//! mesh with quadrics and on adversarial geometry.

mod common;

use common::stats::SplitMix64;
use glam::Mat4;
use glam::{Vec2, Vec3};
use wavetrace::accel::{
    brute_force_closest, prims_from_shapes, Bvh, FlatPrims, APART_QUADRICS_MAX, FLAT_CAPACITY,
    FLAT_PRIMS_MAX, FLAT_PRIMS_MAX_WIDE,
};
use wavetrace::gpu::layout::HitItem;
use wavetrace::gpu::{
    shaders, Buffer, CommandList, DescriptorSet, Kernel, KernelSpec, Location, SpecValues,
};
use wavetrace::render::scene_buffers::SceneRecords;
use wavetrace::scene::{Mesh, Quadric, QuadricKind};

/// `QueryRay` of shaders/tests/bvh_query.comp.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct QueryRay {
    origin: [f32; 3],
    tmin: f32,
    dir: [f32; 3],
    tmax: f32,
}

/// What the GPU answers for each ray: its closest hit, whether any-hit found one, and
/// `bvh_closest_two`'s second-nearest hit.
struct Answers {
    closest: Vec<HitItem>,
    any: Vec<u32>,
    second: Vec<HitItem>,
}

/// Runs closest-, any- and two-hit queries for `rays` on the GPU, with the traversal
/// stack specialized to the tree's depth as the renderer does.
fn gpu_queries(bvh: &Bvh, rays: &[QueryRay]) -> Answers {
    gpu_queries_with_stack(bvh, rays, bvh.stats.stack_depth())
}

/// `gpu_queries` with a traversal stack of `stack_depth` entries.
fn gpu_queries_with_stack(bvh: &Bvh, rays: &[QueryRay], stack_depth: u32) -> Answers {
    gpu_queries_with(bvh, rays, stack_depth, FlatPrims::of(bvh, 0))
}

/// `gpu_queries` with a traversal stack of `stack_depth` entries, testing the
/// primitives in turn as `flat` says (all of them, or those apart before the tree).
fn gpu_queries_with(bvh: &Bvh, rays: &[QueryRay], stack_depth: u32, flat: FlatPrims) -> Answers {
    let device = common::device();
    let (layout, scene) = common::upload_scene(&device, bvh, &SceneRecords::default(), 4, 4);
    let queries = Buffer::from_slice(&device, "queries", rays).unwrap();
    let closest = Buffer::new(&device, "closest", (rays.len() * 16) as u64, Location::Gpu).unwrap();
    let any = Buffer::new(&device, "any", (rays.len() * 4) as u64, Location::Gpu).unwrap();
    let second = Buffer::new(&device, "second", (rays.len() * 16) as u64, Location::Gpu).unwrap();
    let set = DescriptorSet::new(&layout, 1, &[&queries, &closest, &any, &second]).unwrap();
    // The test kernel numbers its own constants 0-2; the vertex constants of the
    // primitives tested in turn keep their ids (gpu::spec_ids::flat_vertex).
    let mut spec = vec![
        (0, stack_depth),
        (1, flat.constants()[0]),
        (2, flat.constants()[1]),
    ];
    spec.extend(
        SpecValues::new()
            .with_flat_vertices(&flat.vertex_words(bvh))
            .ids(),
    );
    let kernel = Kernel::from_spec(
        &device,
        &layout,
        &KernelSpec {
            name: "bvh_query",
            spirv: shaders::TESTS_BVH_QUERY,
            spec,
            inline: false,
        },
    )
    .unwrap();
    let mut cmd = CommandList::new(&device).unwrap();
    let n = rays.len() as u32;
    cmd.dispatch(
        &kernel,
        &[&scene.set, &set],
        bytemuck::bytes_of(&n),
        [n.div_ceil(64), 1, 1],
    );
    cmd.barrier();
    cmd.submit_and_wait().unwrap();
    let mut c: Vec<HitItem> = closest.read(&device).unwrap();
    let mut a: Vec<u32> = any.read(&device).unwrap();
    let mut s: Vec<HitItem> = second.read(&device).unwrap();
    c.truncate(rays.len());
    a.truncate(rays.len());
    s.truncate(rays.len());
    // bvh_query.comp marks a closest hit that bvh_closest_coherent did not find too.
    if let Some(i) = c.iter().position(|h| h.prim == u32::MAX - 2) {
        panic!("ray {i}: bvh_closest_coherent's hit is not bvh_closest's");
    }
    Answers {
        closest: c,
        any: a,
        second: s,
    }
}

/// A uniform point in the box lo..hi.
fn in_box(rng: &mut SplitMix64, lo: Vec3, hi: Vec3) -> Vec3 {
    lo + (hi - lo) * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
}

/// How far a GPU hit distance may lie from the brute force's `t` (float rounding of
/// the two traversals' arithmetic).
fn t_tolerance(t: f32) -> f32 {
    1e-5 * t.abs().max(1e-3)
}

/// Compares GPU results with the CPU brute force and CPU traversal for every ray.
fn check(bvh: &Bvh, rays: &[QueryRay]) -> usize {
    check_with(bvh, rays, FlatPrims::of(bvh, 0))
}

/// `check`, the GPU testing the primitives in turn as `flat` says.
fn check_with(bvh: &Bvh, rays: &[QueryRay], flat: FlatPrims) -> usize {
    let Answers {
        closest,
        any,
        second,
    } = gpu_queries_with(bvh, rays, bvh.stats.stack_depth(), flat);
    let mut hits = 0;
    for (i, r) in rays.iter().enumerate() {
        let (o, d) = (Vec3::from(r.origin), Vec3::from(r.dir));
        let want = brute_force_closest(&bvh.prims, o, d, r.tmin, r.tmax);
        let got = closest[i];
        check_second(bvh, r, i, got, second[i]);
        match want {
            None => assert_eq!(
                got.prim,
                u32::MAX,
                "ray {i}: GPU hit prim {} at t={} where brute force misses",
                got.prim,
                got.t
            ),
            Some(w) => {
                hits += 1;
                assert_ne!(
                    got.prim,
                    u32::MAX,
                    "ray {i} ({o}, {d}): GPU misses, brute force hits prim {} at t={}",
                    w.prim,
                    w.t
                );
                let tol = t_tolerance(w.t);
                assert!(
                    (got.t - w.t).abs() <= tol,
                    "ray {i}: GPU t={} brute force t={}",
                    got.t,
                    w.t
                );
                if got.prim != w.prim {
                    // Only a tie (two primitives at the same distance) may differ.
                    let other = bvh.prims[got.prim as usize];
                    let t_other =
                        brute_force_closest(std::slice::from_ref(&other), o, d, r.tmin, r.tmax)
                            .map(|h| h.t);
                    assert!(
                        t_other.is_some_and(|t| (t - w.t).abs() <= tol),
                        "ray {i}: GPU prim {} is not a tie",
                        got.prim
                    );
                }
            }
        }
        assert_eq!(
            any[i] != 0,
            want.is_some(),
            "ray {i}: any-hit disagrees with brute force"
        );
        let cpu = bvh.closest(o, d, r.tmin, r.tmax);
        assert_eq!(
            cpu.is_some(),
            want.is_some(),
            "ray {i}: CPU traversal disagrees"
        );
    }
    hits
}

/// The second-nearest hit `got2` of ray `i` (whose closest hit on the GPU was `got`)
/// is the nearest hit of every other primitive, by brute force: the same distance (a
/// tie may name another primitive at it), or a miss at tmax.
fn check_second(bvh: &Bvh, r: &QueryRay, i: usize, got: HitItem, got2: HitItem) {
    assert_ne!(
        got2.prim,
        u32::MAX - 1,
        "ray {i}: bvh_closest_two's closest hit is not bvh_closest's"
    );
    let (o, d) = (Vec3::from(r.origin), Vec3::from(r.dir));
    let others: Vec<_> = (bvh.prims.iter().enumerate())
        .filter(|&(k, _)| k as u32 != got.prim)
        .map(|(_, p)| *p)
        .collect();
    let want = if got.prim == u32::MAX {
        None
    } else {
        brute_force_closest(&others, o, d, r.tmin, r.tmax)
    };
    match want {
        None => {
            assert_eq!(
                got2.prim,
                u32::MAX,
                "ray {i}: GPU second hit where brute force has none"
            );
            assert_eq!(got2.t, r.tmax, "ray {i}: a missing second hit lies at tmax");
        }
        Some(w) => {
            assert_ne!(
                got2.prim,
                u32::MAX,
                "ray {i}: GPU misses the second hit at t={}",
                w.t
            );
            assert_ne!(
                got2.prim, got.prim,
                "ray {i}: the second hit repeats the first"
            );
            let tol = t_tolerance(w.t);
            assert!(
                (got2.t - w.t).abs() <= tol,
                "ray {i}: GPU second t={} brute force t={}",
                got2.t,
                w.t
            );
            assert!(
                got2.t >= got.t,
                "ray {i}: the second hit is nearer than the first"
            );
        }
    }
}

fn load_bunny() -> Mesh {
    let scene = common::load(&common::repo("../shared/scenes/nori/bunny/bunny.xml"));
    scene.meshes.into_iter().next().expect("bunny mesh")
}

/// The bunny with spheres, sheared elliptic disks and slanted cylinders among it.
#[test]
fn gpu_closest_and_any_hit_equal_brute_force_on_bunny_and_quadrics() {
    let bunny = load_bunny();
    let (lo, hi) = bunny.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(a, b), &p| (a.min(p), b.max(p)),
    );
    let mut quadrics: Vec<Quadric> = (0..8)
        .map(|k| {
            Quadric::sphere(
                lo + (hi - lo) * Vec3::new(k as f32 / 7.0, 0.5, 0.3),
                0.01 + 0.005 * k as f32,
                0,
            )
        })
        .collect();
    for k in 0..8 {
        let t = k as f32 / 7.0;
        let at = Mat4::from_translation(lo + (hi - lo) * Vec3::new(t, 0.3, 0.6))
            * Mat4::from_rotation_y(1.3 * t)
            * Mat4::from_rotation_x(0.4 + t);
        let (kind, shape) = if k % 2 == 0 {
            // An ellipse, sheared.
            let shear = Mat4::from_cols_array(&[
                1.0, 0.0, 0.0, 0.0, 0.4, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
            ]);
            (
                QuadricKind::Disk,
                shear * Mat4::from_scale(Vec3::new(0.02, 0.01 + 0.004 * t, 1.0)),
            )
        } else {
            (
                QuadricKind::Cylinder,
                Mat4::from_scale(Vec3::new(0.008, 0.008, 0.05 + 0.02 * t)),
            )
        };
        let mut q = Quadric::sphere(Vec3::ZERO, 1.0, 0);
        q.kind = kind;
        q.to_world = at * shape;
        quadrics.push(q);
    }
    let bvh = Bvh::build(prims_from_shapes(&[bunny], &quadrics));
    let mut rng = SplitMix64(7);
    let pad = (hi - lo) * 0.5;
    let rays: Vec<QueryRay> = (0..40_000)
        .map(|i| {
            let o = in_box(&mut rng, lo - pad, hi + pad);
            // Half the rays aim at the mesh's box, half point anywhere.
            let target = if i % 2 == 0 {
                in_box(&mut rng, lo, hi)
            } else {
                in_box(&mut rng, lo - pad, hi + pad)
            };
            let d = (target - o).normalize();
            QueryRay {
                origin: o.into(),
                tmin: 0.0,
                dir: d.into(),
                tmax: if i % 5 == 0 {
                    (target - o).length()
                } else {
                    f32::INFINITY
                },
            }
        })
        .collect();
    let hits = check(&bvh, &rays);
    assert!(
        hits > 10_000,
        "too few rays hit ({hits}) for the test to mean much"
    );
}

/// A scene of a few primitives of every kind, traced without its tree (bvh.glsl's
/// bvh_trace_flat, as the renderer does below accel::FLAT_PRIMS_MAX primitives, or
/// FLAT_PRIMS_MAX_WIDE on llvmpipe at 16 lanes): closest hits equal the brute force's,
/// and any-hit agrees, at the flat traversal's full capacity of primitives of any
/// kind, with fewer primitives (its later steps compiled away), and with triangles
/// beyond that capacity (its loop).
#[test]
fn gpu_flat_traversal_of_a_small_scene_equals_brute_force() {
    // Up to 34 triangles (a fan, winding round more than once), and spheres, disks and
    // cylinders around them.
    let mut fan = Mesh {
        name: "fan".into(),
        ..Default::default()
    };
    fan.positions.push(Vec3::ZERO);
    for k in 0..35 {
        let a = k as f32 * 0.5;
        fan.positions.push(Vec3::new(
            a.cos(),
            a.sin(),
            0.2 * (k % 2) as f32 + 0.01 * k as f32,
        ));
    }
    fan.indices = (1..35).map(|k| [0, k, k + 1]).collect();
    let mut quadrics = Vec::new();
    for k in 0..10 {
        let t = k as f32 / 9.0;
        let c = Vec3::new(1.6 * t - 0.8, 0.7 - 1.4 * t, 0.3 + 0.4 * (k % 3) as f32);
        let mut q = Quadric::sphere(c, 0.15 + 0.05 * t, 0);
        match k % 3 {
            0 => {}
            1 => {
                q.kind = QuadricKind::Disk;
                q.to_world = Mat4::from_translation(c)
                    * Mat4::from_rotation_x(0.7 * t)
                    * Mat4::from_scale(Vec3::new(0.3, 0.2, 1.0));
            }
            _ => {
                q.kind = QuadricKind::Cylinder;
                q.to_world = Mat4::from_translation(c)
                    * Mat4::from_rotation_y(1.1 + t)
                    * Mat4::from_scale(Vec3::new(0.1, 0.1, 0.4));
            }
        }
        quadrics.push(q);
    }
    let mut rng = SplitMix64(11);
    let (lo, hi) = (Vec3::splat(-1.5), Vec3::splat(1.5));
    let rays: Vec<QueryRay> = (0..20_000)
        .map(|i| {
            let o = in_box(&mut rng, lo, hi);
            let target = in_box(&mut rng, Vec3::splat(-0.8), Vec3::splat(0.8));
            QueryRay {
                origin: o.into(),
                tmin: 0.0,
                dir: (target - o).normalize().into(),
                tmax: if i % 4 == 0 {
                    (target - o).length()
                } else {
                    f32::INFINITY
                },
            }
        })
        .collect();
    for (triangles, quadric_count) in [(6, 10), (3, 2), (34, 3)] {
        let mut mesh = fan.clone();
        mesh.indices.truncate(triangles);
        let bvh = Bvh::build(prims_from_shapes(&[mesh], &quadrics[..quadric_count]));
        let n = bvh.prims.len();
        assert!(n <= FLAT_PRIMS_MAX_WIDE);
        let flat = FlatPrims::of(&bvh, FLAT_PRIMS_MAX_WIDE);
        assert_eq!(flat.count as usize, n);
        assert!(flat.flat_only);
        let hits = check_with(&bvh, &rays, flat);
        assert!(hits > 2_000, "{n} primitives: too few rays hit ({hits})");
        // The triangles' vertices as kernel constants (as on llvmpipe at 16 lanes), past
        // the 16 whose kinds the kernels are told too: the same hits.
        let constants = FlatPrims::with_vertex_constants(&bvh, FLAT_PRIMS_MAX_WIDE);
        assert!(constants.vertices);
        assert_eq!(
            check_with(&bvh, &rays, constants),
            hits,
            "{n} primitives: constants"
        );
        // The tree: with its quadrics apart where there are few (2), else holding them.
        let tree = FlatPrims::of(&bvh, n - 1);
        assert!(!tree.flat_only);
        let apart = if quadric_count <= APART_QUADRICS_MAX {
            quadric_count
        } else {
            0
        };
        assert_eq!((tree.count as usize, bvh.apart as usize), (apart, apart));
        assert_eq!(check_with(&bvh, &rays, tree), hits, "{n} primitives: tree");
    }
    // The renderer's threshold lies within what the traversal holds of every kind.
    assert!((1..=FLAT_CAPACITY).contains(&FLAT_PRIMS_MAX));
}

/// A closed cube of 12 triangles sharing edges and vertices, and a fine grid: rays
/// aimed exactly at shared edges and vertices must hit (watertightness), never leak.
#[test]
fn gpu_rays_through_shared_edges_and_vertices_never_leak() {
    let n = 16;
    let mut grid = Mesh {
        name: "grid".into(),
        ..Default::default()
    };
    for j in 0..=n {
        for i in 0..=n {
            grid.positions
                .push(Vec3::new(i as f32 / n as f32, j as f32 / n as f32, 0.0));
            grid.uvs.push(Vec2::ZERO);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            grid.indices.push([a, a + 1, a + n + 2]);
            grid.indices.push([a, a + n + 2, a + n + 1]);
        }
    }
    let bvh = Bvh::build(prims_from_shapes(&[grid], &[]));
    let mut rng = SplitMix64(3);
    let mut rays = Vec::new();
    for j in 1..n {
        for i in 1..n {
            // A vertex, the midpoint of a horizontal edge and of a diagonal.
            for (x, y) in [
                (i as f32, j as f32),
                (i as f32 + 0.5, j as f32),
                (i as f32 + 0.5, j as f32 + 0.5),
            ] {
                let target = Vec3::new(x / n as f32, y / n as f32, 0.0);
                let o = target + Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 1.0);
                rays.push(QueryRay {
                    origin: o.into(),
                    tmin: 0.0,
                    dir: (target - o).normalize().into(),
                    tmax: f32::INFINITY,
                });
            }
        }
    }
    let Answers { closest, any, .. } = gpu_queries(&bvh, &rays);
    for (i, (c, a)) in closest.iter().zip(&any).enumerate() {
        assert_ne!(
            c.prim,
            u32::MAX,
            "ray {i} through a shared edge or vertex leaked"
        );
        assert_eq!(*a, 1, "any-hit ray {i} leaked");
    }
    check(&bvh, &rays);
}

/// A soup of large random triangles crossing each other: a ray meets many, in leaves
/// whose boxes overlap, so the traversal finds nearer hits after farther ones and the
/// two-hit query must reorder what it keeps.
#[test]
fn gpu_nearest_two_hits_in_a_triangle_soup_equal_brute_force() {
    let mut rng = SplitMix64(5);
    let mut soup = Mesh {
        name: "soup".into(),
        ..Default::default()
    };
    for k in 0..300u32 {
        let c = in_box(&mut rng, Vec3::splat(-1.0), Vec3::splat(1.0));
        for _ in 0..3 {
            soup.positions
                .push(c + 0.6 * in_box(&mut rng, Vec3::splat(-1.0), Vec3::splat(1.0)));
            soup.uvs.push(Vec2::ZERO);
        }
        soup.indices.push([3 * k, 3 * k + 1, 3 * k + 2]);
    }
    let bvh = Bvh::build(prims_from_shapes(&[soup], &[]));
    let rays: Vec<QueryRay> = (0..20_000)
        .map(|_| {
            let o = in_box(&mut rng, Vec3::splat(-2.0), Vec3::splat(2.0));
            let target = in_box(&mut rng, Vec3::splat(-0.5), Vec3::splat(0.5));
            QueryRay {
                origin: o.into(),
                tmin: 0.0,
                dir: (target - o).normalize().into(),
                tmax: f32::INFINITY,
            }
        })
        .collect();
    check(&bvh, &rays);
    let second = gpu_queries(&bvh, &rays).second;
    let found = second.iter().filter(|h| h.prim != u32::MAX).count();
    assert!(found > 15_000, "only {found} rays met two triangles");
}

#[test]
fn gpu_traversal_of_an_empty_scene_misses() {
    let bvh = Bvh::build(Vec::new());
    let rays = [QueryRay {
        origin: [0.0; 3],
        tmin: 0.0,
        dir: [0.0, 0.0, 1.0],
        tmax: f32::INFINITY,
    }];
    let answers = gpu_queries(&bvh, &rays);
    assert_eq!(answers.closest[0].prim, u32::MAX);
    assert_eq!(answers.any[0], 0);
    assert_eq!(answers.second[0].prim, u32::MAX);
}

/// A ladder of exponentially spaced and sized rungs builds a tree as deep as the build
/// allows (SAH splits off a few of the largest rungs per level). Each rung's box spans
/// the x axis but the rung itself misses it, except the last and largest, which is in
/// the root's far subtree: a ray along the axis descends the whole spine, deferring a
/// subtree at every level, and finds its hit in the bottom entry. The GPU traversal,
/// its register stack specialized to the tree's depth, must agree with brute force on
/// every ray, and the same rays must lose hits with a stack two entries short.
#[test]
fn gpu_traversal_of_a_tree_at_full_stack_depth_equals_brute_force() {
    let mut mesh = Mesh {
        name: "ladder".into(),
        ..Default::default()
    };
    let rungs = 600;
    for i in 0..rungs {
        let s = 1.09f32.powi(i - 300);
        let (a, b, c) = if i + 1 < rungs {
            // Box y in [-s, s], z in [-s/2, s]; the edge from a to c passes above the
            // axis (z = s/4 at y = 0).
            (Vec2::new(-s, s), Vec2::new(s, s), Vec2::new(s, -0.5 * s))
        } else {
            (
                Vec2::new(-s, -s),
                Vec2::new(3.0 * s, -s),
                Vec2::new(-s, 3.0 * s),
            )
        };
        let base = mesh.positions.len() as u32;
        mesh.positions
            .extend([a, b, c].map(|p| Vec3::new(s, p.x, p.y)));
        mesh.uvs.extend([Vec2::ZERO; 3]);
        mesh.indices.push([base, base + 1, base + 2]);
    }
    let bvh = Bvh::build(prims_from_shapes(&[mesh], &[]));
    assert!(
        bvh.stats.max_depth >= 24,
        "the ladder built only {} levels deep",
        bvh.stats.max_depth
    );
    let mut rng = SplitMix64(11);
    let smallest = 1.09f32.powi(-300);
    let rays: Vec<QueryRay> = (0..20_000)
        .map(|i| {
            if i % 2 == 0 {
                // Along the axis from before the first rung: the deep case.
                let o = smallest
                    * Vec3::new(0.5, rng.next_f32() * 0.2 - 0.1, rng.next_f32() * 0.2 - 0.1);
                QueryRay {
                    origin: o.into(),
                    tmin: 0.0,
                    dir: [1.0, 0.0, 0.0],
                    tmax: f32::INFINITY,
                }
            } else {
                let x = 1.09f32.powf(rng.next_f32() * 610.0 - 305.0);
                let o = x * Vec3::new(1.0, rng.next_f32() * 2.0 - 1.0, rng.next_f32() * 2.0 - 1.0);
                let d = Vec3::new(
                    rng.next_f32() - 0.5,
                    rng.next_f32() - 0.5,
                    rng.next_f32() - 0.5,
                );
                QueryRay {
                    origin: o.into(),
                    tmin: 0.0,
                    dir: d.normalize().into(),
                    tmax: f32::INFINITY,
                }
            }
        })
        .collect();
    let hits = check(&bvh, &rays);
    assert!(hits > 10_000, "too few rays hit ({hits})");
    // The axial rays do need that depth: with two entries fewer they miss.
    let short = gpu_queries_with_stack(&bvh, &rays, bvh.stats.stack_depth() - 2).closest;
    let lost = short
        .iter()
        .step_by(2)
        .filter(|h| h.prim == u32::MAX)
        .count();
    assert!(
        lost > 1000,
        "a stack 2 entries short lost only {lost} axial hits"
    );
}

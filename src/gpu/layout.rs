//! The constants that go with the GPU records (kinds, flags, features), and the
//! records themselves, re-exported from [`super::records`] where they are declared
//! once (the GLSL structs and loaders are generated from them by build.rs).
//!
//! Each constant is mirrored by a `#define` in `shaders/scene/layout.glsl`; the tests
//! at the bottom check those, and the generated structs' std430 layout against Rust's.

pub use super::records::*;

/// Primitive kinds in [`Prim::kind`].
pub const PRIM_TRIANGLE: u32 = 0;
pub const PRIM_SPHERE: u32 = 1;
pub const PRIM_DISK: u32 = 2;
pub const PRIM_CYLINDER: u32 = 3;
/// An instance in the top-level tree of a scene with instances (`accel::instance`):
/// `p0`, `p1`, `p2` the rows of its world-to-object map's 3×3 (its world box is in
/// the top-level nodes only), `shape` its group's bottom-level root node, `index` the
/// instance number (its translation's texel after the primitives).
pub const PRIM_INSTANCE: u32 = 4;
/// Formerly the kind of an instance's transform records; those
/// (`accel::instance`, one per instance after every primitive) now hold the
/// translation's bits in their kind word, as no tree reaches them. Kept so that the
/// number stays taken.
pub const PRIM_INSTANCE_DATA: u32 = 5;
/// An `sdfgrid` (`scene::shape::sdfgrid`): `p0`, `p1` its box, `p2[0]` the bits of
/// its header's offset in the grid buffer, `index` its quadric number.
pub const PRIM_SDFGRID: u32 = 7;
/// A segment of a `linearcurve` (`scene::shape::linearcurve`): `p0`, `p1` its control
/// points, `p2` = (radius at p0, radius at p1, the shape's segment count, negated for
/// a curve's first segment, which alone has its start sphere: Embree's), `index` its
/// number among the shape's segments.
pub const PRIM_LINEAR_CURVE: u32 = 8;
/// A segment of a `bsplinecurve` (`scene::shape::bsplinecurve`): `p0`, `p1` its box,
/// `p2` = (the bits of the grid-buffer offset of its four control points, `x y z
/// radius` each, the shape's segment count, 0), `index` its number among the shape's
/// segments. The control points are a side table in the grid buffer (after the
/// sdfgrids), as a segment's 16 numbers do not fit a record.
pub const PRIM_BSPLINE_CURVE: u32 = 9;
/// An ellipsoid of an `ellipsoids` shape (`scene::shape::ellipsoids`): `p0`, `p1` its
/// box, `p2` = (the bits of the grid-buffer offset of its 12 numbers: centre and the
/// rows of its map to the unit sphere, 0, 0), `index` its number in the shape.
pub const PRIM_ELLIPSOID: u32 = 10;

/// Marks an absent index (no emitter, no hit).
pub const NONE: u32 = u32::MAX;
/// The mesh has per-vertex normals.
pub const SHAPE_HAS_NORMALS: u32 = 1;
/// The mesh has per-vertex texture coordinates.
pub const SHAPE_HAS_UVS: u32 = 2;
/// Normals point inwards (Mitsuba `flip_normals`).
pub const SHAPE_FLIP_NORMALS: u32 = 4;
/// A `null` BSDF: an index-matched boundary that rays pass straight through.
pub const SHAPE_NULL_BSDF: u32 = 8;
/// The shape bounds media (Mitsuba `interior`/`exterior`): a ray leaving it towards
/// its normal enters the exterior medium, against it the interior one.
pub const SHAPE_MEDIUM_TRANSITION: u32 = 16;
/// A `thindielectric` BSDF: the volumetric path tracers cross the surface as a null
/// one with probability 1 - R' (Mitsuba's null transmission lobe), and shadow rays
/// pass it attenuated by 1 - R'.
pub const SHAPE_THIN_DIELECTRIC: u32 = 32;
/// A quadric whose `to_world` mirrors: its object frame is left-handed, which the
/// uvs and tangents of spheres and cylinders need (see [`Prim`]).
pub const SHAPE_MIRRORED: u32 = 64;
/// Every vertex normal of the mesh lies on its triangle's side (by a margin,
/// [`crate::scene::Mesh::normals_agree`]): the shading normal never turns the geometric
/// one, so a null crossing or a sampled point of a light needs neither
/// (shaders/shape/surface.glsl, surface_at_as). Set on null-BSDF and emitting meshes,
/// the only ones read that way.
pub const SHAPE_NORMALS_AGREE: u32 = 128;
/// No medium in one half of [`ShapeRecord::media`].
pub const MEDIUM_NONE16: u32 = 0xffff;

/// [`ShapeRecord::media`] of a shape with these media (indices below 0xffff).
pub fn shape_media(interior: Option<u32>, exterior: Option<u32>) -> u32 {
    interior.unwrap_or(MEDIUM_NONE16) | exterior.unwrap_or(MEDIUM_NONE16) << 16
}

/// Medium kinds in [`MediumRecord::kind`].
pub const MEDIUM_HOMOGENEOUS: u32 = 0;
pub const MEDIUM_GRID: u32 = 1;
/// [`MediumRecord::flags`]: Mitsuba `sample_emitters` (next-event estimation at
/// scattering points in the medium).
pub const MEDIUM_SAMPLE_EMITTERS: u32 = 1;
/// [`MediumRecord::flags`]: the albedo grid has three channels.
pub const MEDIUM_ALBEDO_RGB: u32 = 2;
/// [`MediumRecord::flags`]: the density grid is in the packed-density buffer at
/// `data`, one 16-byte texel per voxel (`scene::medium::record::pack_density`), instead of
/// the grid buffer.
pub const MEDIUM_DENSITY_PACKED: u32 = 4;

/// Surface features a scene uses (`SceneRecords::surface_features`): a specialization
/// constant of the kernels that compute hit geometry (surface.glsl), so the code of
/// absent ones compiles away. Spheres:
pub const SURFACE_FEATURE_SPHERES: u32 = 1;
/// Meshes with vertex normals ([`SHAPE_HAS_NORMALS`]).
pub const SURFACE_FEATURE_NORMALS: u32 = 2;
/// Meshes with vertex uvs ([`SHAPE_HAS_UVS`]).
pub const SURFACE_FEATURE_UVS: u32 = 4;
/// Disks.
pub const SURFACE_FEATURE_DISKS: u32 = 8;
/// Cylinders.
pub const SURFACE_FEATURE_CYLINDERS: u32 = 16;
/// Signed-distance grids ([`PRIM_SDFGRID`]).
pub const SURFACE_FEATURE_SDFGRIDS: u32 = 128;
/// Linear curve segments ([`PRIM_LINEAR_CURVE`]).
pub const SURFACE_FEATURE_LINEAR_CURVES: u32 = 64;
/// B-spline curve segments ([`PRIM_BSPLINE_CURVE`]).
pub const SURFACE_FEATURE_BSPLINE_CURVES: u32 = 256;
/// Ellipsoids ([`PRIM_ELLIPSOID`]).
pub const SURFACE_FEATURE_ELLIPSOIDS: u32 = 512;
/// The `SURFACE_FEATURE_*` bit of each quadric `PRIM_*` kind; the BVH traversal's
/// primitive mask (specialization constant of intersect, shade and shadow) is made of
/// these bits too.
pub const fn surface_feature_of_prim(kind: u32) -> u32 {
    match kind {
        PRIM_SPHERE => SURFACE_FEATURE_SPHERES,
        PRIM_DISK => SURFACE_FEATURE_DISKS,
        PRIM_CYLINDER => SURFACE_FEATURE_CYLINDERS,
        PRIM_SDFGRID => SURFACE_FEATURE_SDFGRIDS,
        PRIM_LINEAR_CURVE => SURFACE_FEATURE_LINEAR_CURVES,
        PRIM_BSPLINE_CURVE => SURFACE_FEATURE_BSPLINE_CURVES,
        PRIM_ELLIPSOID => SURFACE_FEATURE_ELLIPSOIDS,
        _ => 0,
    }
}

/// Medium features a scene uses (`SceneRecords::medium_features`): a specialization
/// constant of the kernels with medium code, so the code of the others compiles away.
/// That matters on llvmpipe, which runs the code of a branch whatever its lanes decide.
/// Homogeneous media:
pub const MEDIUM_FEATURE_HOMOGENEOUS: u32 = 1;
/// A packed one-channel density grid ([`MEDIUM_DENSITY_PACKED`]).
pub const MEDIUM_FEATURE_PACKED1: u32 = 2;
/// A packed three-channel density grid.
pub const MEDIUM_FEATURE_PACKED3: u32 = 4;
/// A density grid left in the grid buffer (too large to pack).
pub const MEDIUM_FEATURE_DENSITY_WORDS: u32 = 8;
/// A one-channel grid (density or albedo) in the grid buffer.
pub const MEDIUM_FEATURE_WORDS1: u32 = 16;
/// A three-channel grid (density or albedo) in the grid buffer.
pub const MEDIUM_FEATURE_WORDS3: u32 = 32;
/// An albedo grid.
pub const MEDIUM_FEATURE_ALBEDO_GRID: u32 = 64;
/// Every grid feature: the scene has grid media.
pub const MEDIUM_FEATURE_GRIDS: u32 =
    MEDIUM_FEATURE_PACKED1 | MEDIUM_FEATURE_PACKED3 | MEDIUM_FEATURE_DENSITY_WORDS;

/// BSDF kinds in [`BsdfRecord::kind`]: `scene::bsdf::kinds::KINDS`, from which
/// build.rs generates their GLSL constants and dispatch.
/// [`BsdfRecord::flags`]: Mitsuba `twosided` around the model.
pub const BSDF_TWOSIDED: u32 = 1;
/// [`BsdfRecord::flags`]: plastics with `nonlinear` = true.
pub const BSDF_NONLINEAR: u32 = 2;
/// [`BsdfRecord::flags`]: `normalmap` with `flip_invalid_normals` = true (Mitsuba's default).
pub const BSDF_NORMALMAP_FLIP: u32 = 4;
/// [`BsdfRecord::flags`]: `normalmap` with `use_shadowing_function` = true (Mitsuba's default).
pub const BSDF_NORMALMAP_SHADOWING: u32 = 8;
/// [`BsdfRecord::flags`]: textures replace entries of the table (`principled`:
/// `scene::bsdf::principled::T_TEXTURED`).
pub const BSDF_TABLE_TEXTURES: u32 = 16;
/// [`BsdfRecord::distribution`] values.
pub const BSDF_BECKMANN: u32 = 0;
pub const BSDF_GGX: u32 = 1;

/// Camera kinds in [`Frame::camera_kind`] (`scene::Projection`).
pub const CAMERA_PERSPECTIVE: u32 = 0;
pub const CAMERA_ORTHOGRAPHIC: u32 = 1;
pub const CAMERA_THINLENS: u32 = 2;
pub const CAMERA_RADIANCEMETER: u32 = 3;
pub const CAMERA_DISTANT: u32 = 4;
pub const CAMERA_IRRADIANCEMETER: u32 = 5;

/// Emitter kinds in [`EmitterRecord::kind`].
pub const EMITTER_POINT: u32 = 0;
pub const EMITTER_AREA: u32 = 1;
pub const EMITTER_CONSTANT: u32 = 2;
pub const EMITTER_SPOT: u32 = 3;
/// Mitsuba `envmap`: a lat-long image around the scene.
pub const EMITTER_ENVMAP: u32 = 4;
/// Mitsuba `directional`: light from infinity along `EmitterRecord::axis` (kinds start
/// past the mask bits 5-8 below, as each kind is also a bit of the mask).
pub const EMITTER_DIRECTIONAL: u32 = 9;
/// Mitsuba `projector`: a delta-position light through an image plane.
pub const EMITTER_PROJECTOR: u32 = 10;
/// Mitsuba's `directionalarea`: an area emitter emitting along its normal only.
pub const EMITTER_DIRECTIONAL_AREA: u32 = 11;
/// Bit of the emitter-kinds mask (specialization constant `SCENE_EMITTER_KINDS`, a bit per
/// kind above) that stands for area emitters on spheres; `EMITTER_AREA`'s bit then
/// means area emitters on meshes.
pub const EMITTER_KIND_BIT_SPHERE_AREA: u32 = 5;
/// Bit of the emitter-kinds mask for area emitters on disks and cylinders.
pub const EMITTER_KIND_BIT_QUADRIC_AREA: u32 = 6;
/// Bit of the emitter-kinds mask for area emitters sampled by their texture
/// (`EmitterRecord::dist_width` > 0, on meshes or spheres), which then set neither
/// `EMITTER_AREA`'s bit nor `EMITTER_KIND_BIT_SPHERE_AREA`: where every light is one,
/// the code of uniform area sampling compiles out.
pub const EMITTER_KIND_BIT_TEXTURE_SAMPLED: u32 = 7;
/// Bit of the emitter-kinds mask set beside [`EMITTER_KIND_BIT_TEXTURE_SAMPLED`] where
/// a texture-sampled emitter lies on a sphere: without it that code compiles out.
pub const EMITTER_KIND_BIT_TEXTURE_SPHERE: u32 = 8;

/// Texture kinds in [`TextureRecord::kind`] (`shaders/texture/texture.glsl`).
pub const TEXTURE_BITMAP: u32 = 0;
pub const TEXTURE_CHECKERBOARD: u32 = 1;
pub const TEXTURE_NOISE: u32 = 2;
pub const TEXTURE_MARBLE: u32 = 3;
/// Mitsuba `rawconstant`: `color0` everywhere.
pub const TEXTURE_CONSTANT: u32 = 4;
/// Mitsuba `mesh_attribute`: `offset` a table of one texel word per shape (the start
/// of its values, or `NONE`), `width` the channels (1 or 3), `frequency` the scale.
pub const TEXTURE_MESH_ATTRIBUTE: u32 = 5;
/// [`TextureRecord::flags`] of a mesh attribute: per face (else per vertex).
pub const TEXTURE_ATTRIBUTE_FACE: u32 = 1;
/// [`TextureRecord::flags`]: nearest-neighbour lookups (else bilinear).
pub const TEXTURE_NEAREST: u32 = 1;
/// [`TextureRecord::flags`] bits 1-2: the wrap mode.
pub const TEXTURE_WRAP_SHIFT: u32 = 1;
pub const TEXTURE_WRAP_REPEAT: u32 = 0;
pub const TEXTURE_WRAP_MIRROR: u32 = 1;
pub const TEXTURE_WRAP_CLAMP: u32 = 2;
/// Bits of the shade kernel's texture mask (specialization constant `SCENE_TEXTURES`) beside the
/// kinds (`1 << TEXTURE_*`): code for features a scene lacks compiles out.
pub const TEXTURE_FEATURE_BSDF: u32 = 256;
pub const TEXTURE_FEATURE_NORMALMAP: u32 = 512;
pub const TEXTURE_FEATURE_ENVMAP: u32 = 1024;
pub const TEXTURE_FEATURE_AREA: u32 = 2048;
/// Surface points need fewer texture lookups than the scene has textured BSDF
/// parameters and emitters: `bsdf_textured_point` (bsdf_textured.glsl) loops over them.
pub const TEXTURE_FEATURE_LOOKUP_LOOP: u32 = 4096;
/// Some BSDF record has textured table entries ([`BSDF_TABLE_TEXTURES`]):
/// `bsdf_textured_point` looks them up.
pub const TEXTURE_FEATURE_TABLE: u32 = 8192;
/// A spot light's `texture` or a projector's `irradiance` texture (read by emitter
/// sampling and photon emission only).
pub const TEXTURE_FEATURE_EMITTER_PROFILE: u32 = 16384;
/// Bit `TEXTURE_FEATURE_PARAM_SHIFT + k`: some BSDF textures its parameter k (0
/// reflectance, 1 specular, 2 transmittance, 3 alpha_u, 4 alpha_v, 6 cond_eta, 7
/// cond_k, 8 eta), as `SURFACE_TEX_*` in bsdf_textured.glsl.
pub const TEXTURE_FEATURE_PARAM_SHIFT: u32 = 16;

/// Most emitter prims [`Frame::emitter_prims`] holds.
pub const MAX_EMITTER_PRIMS: usize = 16;

/// Sampler kinds ([`Frame::sampler_kind`]), mirrored in layout.glsl.
pub const SAMPLER_INDEPENDENT: u32 = 0;
pub const SAMPLER_STRATIFIED: u32 = 1;
pub const SAMPLER_MULTIJITTER: u32 = 2;
pub const SAMPLER_ORTHOGONAL: u32 = 3;
pub const SAMPLER_LDSAMPLER: u32 = 4;
pub const SAMPLER_ZSOBOL: u32 = 5;
pub const SAMPLER_SOBOL: u32 = 6;
pub const SAMPLER_PMJ02BN: u32 = 7;
/// `orthogonal` of strength above 2 (Bush's construction; Bose's for strength 2).
pub const SAMPLER_ORTHOGONAL_BUSH: u32 = 8;
/// [`Frame::sampler_flags`]: jitter within strata.
pub const SAMPLER_JITTER: u32 = 1;
pub const SAMPLER_STRENGTH_SHIFT: u32 = 8;
pub const SAMPLER_SCRAMBLE_SHIFT: u32 = 16;
/// Randomizations of base-2 digits (Sobol' samplers).
pub const SAMPLER_SCRAMBLE_NONE: u32 = 0;
pub const SAMPLER_SCRAMBLE_XOR: u32 = 1;
pub const SAMPLER_SCRAMBLE_FAST_OWEN: u32 = 2;
pub const SAMPLER_SCRAMBLE_OWEN: u32 = 3;

/// The current ray was sampled from a delta lobe (no MIS on the emitter it hits).
pub const PATH_DELTA: u32 = 1;
/// Set by the medium stage for path_shade within one dispatch, never stored: the
/// stage chose the reflection lobe of the thin dielectric the ray hit.
pub const PATH_THIN_REFLECT: u32 = 2;
/// The camera path counts for the film's alpha (Mitsuba's `valid_ray`): it found a
/// surface or scattered in a medium, or it sees a visible environment. Set by
/// `generate` and by `shade` at depth 0, kept through the path.
pub const PATH_COVERED: u32 = 4;

/// Reconstruction filters: specialization constant `FILM_FILTER` of `film_gather`
/// (`scene::film::Filter`).
pub const FILTER_BOX: u32 = 0;
pub const FILTER_TENT: u32 = 1;
pub const FILTER_GAUSSIAN: u32 = 2;
pub const FILTER_MITCHELL: u32 = 3;
pub const FILTER_LANCZOS: u32 = 4;
/// A film sample's flags: the sample is finite (NaN and infinite ones are dropped) ...
pub const FILM_SAMPLE_VALID: u32 = 1;
/// ... and its camera path was covered ([`PATH_COVERED`]).
pub const FILM_SAMPLE_COVERED: u32 = 2;

/// [`VisiblePoint::flags`]: the BSDF has a normal map.
pub const VISIBLE_POINT_NORMAL_MAP: u32 = 1;

/// Threads per workgroup of every wavefront kernel (`WORKGROUP_SIZE` in GLSL).
pub const WORKGROUP_SIZE: u32 = 128;

#[cfg(test)]
mod tests {
    //! The GLSL mirror must agree with these structs: parse `layout.glsl` and the
    //! `records.glsl` build.rs generates, lay every struct out by the std430 rules (GLSL 4.60 spec, section 7.6.2.2) and compare
    //! each field's name, order and offset, and each struct's size.

    use super::*;
    use std::collections::HashMap;
    use std::mem::{offset_of, size_of};

    /// (size, alignment) of a GLSL type under std430.
    fn std430(ty: &str) -> (usize, usize) {
        match ty {
            "float" | "uint" | "int" | "bool" => (4, 4),
            "vec2" | "uvec2" | "ivec2" => (8, 8),
            "vec3" | "uvec3" | "ivec3" => (12, 16),
            "vec4" | "uvec4" | "ivec4" => (16, 16),
            "mat4" => (64, 16),
            _ => panic!("layout test does not know GLSL type {ty}"),
        }
    }

    /// Struct name -> (fields with offsets, size), in file order.
    fn parse_glsl(src: &str) -> HashMap<String, (Vec<(String, usize)>, usize)> {
        let no_comments: String = src
            .lines()
            .map(|l| l.split("//").next().unwrap_or(""))
            .filter(|l| !l.trim_start().starts_with('#'))
            .collect::<Vec<_>>()
            .join("\n");
        let mut out = HashMap::new();
        let mut rest = no_comments.as_str();
        while let Some(pos) = rest.find("struct ") {
            rest = &rest[pos + 7..];
            let open = rest.find('{').expect("struct body");
            let close = rest.find('}').expect("struct end");
            let name = rest[..open].trim().to_string();
            let (mut offset, mut align_max) = (0usize, 4usize);
            let mut fields = Vec::new();
            for decl in rest[open + 1..close].split(';') {
                let decl = decl.trim();
                if decl.is_empty() {
                    continue;
                }
                let mut parts = decl.split_whitespace();
                let ty = parts.next().expect("type");
                let var = parts.next().expect("field name");
                let (field, count) = match var.find('[') {
                    Some(b) => (
                        &var[..b],
                        var[b + 1..var.len() - 1]
                            .parse::<usize>()
                            .expect("array length"),
                    ),
                    None => (var, 1),
                };
                let (size, align) = std430(ty);
                let stride = size.next_multiple_of(align);
                offset = offset.next_multiple_of(align);
                fields.push((field.to_string(), offset));
                offset += if count == 1 { size } else { stride * count };
                align_max = align_max.max(align);
            }
            out.insert(name, (fields, offset.next_multiple_of(align_max)));
            rest = &rest[close..];
        }
        out
    }

    macro_rules! rust_layout {
        ($t:ty, $($f:ident),+) => {
            (
                stringify!($t).to_string(),
                vec![$((stringify!($f).to_string(), offset_of!($t, $f))),+],
                size_of::<$t>(),
            )
        };
    }

    /// A struct's name, its fields with their offsets, and its size.
    type Layout = (String, Vec<(String, usize)>, usize);

    /// The scene's records (set 0, read through scene_bindings.glsl).
    fn scene_record_layouts() -> Vec<Layout> {
        vec![
            rust_layout!(
                BvhNode,
                left_min,
                left_index,
                left_max,
                left_count,
                right_min,
                right_index,
                right_max,
                right_count
            ),
            rust_layout!(Prim, p0, shape, p1, index, p2, kind),
            rust_layout!(ShapeRecord, bsdf, emitter, flags, media),
            rust_layout!(TriangleRecord, v0, v1, v2, pad0),
            rust_layout!(Vertex, nx, ny, nz, u, v, pad0, pad1, pad2),
            rust_layout!(
                BsdfRecord,
                reflectance,
                kind,
                specular,
                flags,
                transmittance,
                eta,
                cond_eta,
                alpha_u,
                cond_k,
                alpha_v,
                distribution,
                specular_weight,
                internal,
                tex_eta,
                table,
                tex_reflectance,
                tex_specular,
                tex_transmittance,
                tex_alpha_u,
                tex_alpha_v,
                normal_map,
                tex_cond_eta,
                tex_cond_k
            ),
            rust_layout!(
                EmitterRecord,
                position,
                kind,
                radiance,
                shape,
                axis,
                cos_cutoff,
                cutoff,
                inv_transition,
                area,
                radius,
                tri_first,
                tri_count,
                prim,
                prim_kind,
                texture,
                dist_offset,
                dist_width,
                dist_height,
                to_world_x,
                to_world_y,
                to_world_z
            ),
            rust_layout!(
                TextureRecord,
                kind,
                offset,
                width,
                height,
                flags,
                octaves,
                seed,
                pad0,
                color0,
                frequency,
                color1,
                variation,
                to_uv_u,
                to_uv_v
            ),
            rust_layout!(AliasEntry, prob, alias, pmf, prim),
            rust_layout!(
                MediumRecord,
                sigma_t,
                kind,
                albedo,
                g,
                world_to_grid,
                res,
                data,
                maj_res,
                maj_data,
                majorant,
                channels,
                flags,
                albedo_data
            ),
        ]
    }

    /// The frame, the wavefront's records and its counters and push constants.
    fn frame_and_queue_layouts() -> Vec<Layout> {
        vec![
            rust_layout!(
                Frame,
                camera_to_world,
                tan_half_fov,
                near_clip,
                far_clip,
                width,
                height,
                seed,
                point_light_count,
                ao_max_t,
                ao_uniform,
                max_depth,
                emitter_count,
                rr_depth,
                env_emitter,
                hide_emitters,
                camera_medium,
                sampler_kind,
                sample_count,
                sampler_res_x,
                sampler_res_y,
                sampler_flags,
                sampler_width,
                sampler_height,
                emitter_strata,
                emitter_prims,
                photon_alias,
                camera_kind,
                aperture_radius,
                focus_distance,
                batch_to_world,
                batch_view,
                batch_lens
            ),
            rust_layout!(
                PathState,
                throughput,
                pixel,
                radiance,
                sample_index,
                bsdf_pdf,
                flags,
                eta_scale,
                medium
            ),
            rust_layout!(RayItem, origin, path, dir, tmax),
            rust_layout!(HitItem, t, u, v, prim),
            rust_layout!(ShadowItem, origin, path, dir, tmax, contribution, medium),
            rust_layout!(
                Counters,
                ray_count,
                rays_traced,
                discarded,
                deferred,
                deferred_total,
                head_pad,
                tails
            ),
            rust_layout!(
                DispatchArgs,
                rays,
                shadows,
                hits,
                misses,
                deferred_rays,
                deferred_shadows
            ),
            rust_layout!(
                Push,
                path_count,
                pixel_base,
                sample_base,
                depth,
                queue_in,
                capacity,
                sample_slot,
                film_row,
                film_rows,
                frame_index,
                pad1,
                pad2
            ),
        ]
    }

    /// The film's, photon mapping's and the viewer's structs.
    fn film_and_photon_layouts() -> Vec<Layout> {
        vec![
            rust_layout!(
                FilmParams,
                region_x,
                region_y,
                region_width,
                region_height,
                crop_x,
                crop_y,
                crop_width,
                crop_height,
                key_x,
                key_y,
                key_width,
                reach,
                slots,
                coverage,
                pad0,
                pad1,
                filter_params
            ),
            rust_layout!(Photon, position, path, power, wi),
            rust_layout!(PhotonPath, power, index, start_power, stored, pad0, pad1),
            rust_layout!(
                PhotonParams,
                scene_center,
                scene_radius,
                cell_size,
                inv_cell_size,
                table_mask,
                capacity,
                radius,
                gather_scale,
                emission_scale,
                path_limit,
                store_first,
                max_bounces,
                iteration,
                first_pixel
            ),
            rust_layout!(PhotonCounters, stored, max_radius, pad0, pad1),
            rust_layout!(VisiblePoint, p, bsdf, wo, u, n, v, beta, alpha2, n0, flags),
            rust_layout!(SppmPixel, tau, radius, ld, n, phi, m),
            rust_layout!(TonemapPush, width, height, scale, luminance),
            rust_layout!(
                LetterboxPush,
                window_width,
                window_height,
                x,
                y,
                width,
                height,
                picture_width,
                picture_height,
                step_x,
                step_y,
                bar,
                bgra
            ),
        ]
    }

    /// The GLSL structs: layout.glsl and the records.glsl build.rs generates.
    fn glsl_structs() -> HashMap<String, (Vec<(String, usize)>, usize)> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/scene/layout.glsl");
        let mut src = std::fs::read_to_string(path).expect("read layout.glsl");
        let path = concat!(env!("OUT_DIR"), "/glsl/generated/records.glsl");
        src += &std::fs::read_to_string(path).expect("read the generated records.glsl");
        parse_glsl(&src)
    }

    /// Every GLSL struct (generated from `records.rs`, so this checks the generator)
    /// has the fields, std430 offsets and size of its Rust struct (`offset_of!`).
    #[test]
    fn glsl_mirror_matches_rust_layout() {
        let glsl = glsl_structs();
        let mut rust = scene_record_layouts();
        rust.extend(frame_and_queue_layouts());
        rust.extend(film_and_photon_layouts());
        for (name, fields, size) in &rust {
            let (gfields, gsize) = glsl
                .get(name)
                .unwrap_or_else(|| panic!("struct {name} is missing from the GLSL"));
            assert_eq!(
                gfields, fields,
                "fields or offsets of {name} differ between Rust and GLSL"
            );
            assert_eq!(gsize, size, "size of {name} differs between Rust and GLSL");
        }
        assert_eq!(
            glsl.len(),
            rust.len(),
            "the GLSL has structs the Rust side does not check"
        );
    }

    /// `RECORDS` (what build.rs generates GLSL from) names every struct checked above,
    /// with the fields and offsets `offset_of!` gives.
    #[test]
    fn record_table_matches_rust_layout() {
        let mut rust = scene_record_layouts();
        rust.extend(frame_and_queue_layouts());
        rust.extend(film_and_photon_layouts());
        let table: Vec<Layout> = RECORDS
            .iter()
            .map(|r| {
                let fields = r.fields.iter().map(|f| (f.name.to_string(), f.offset));
                (r.name.to_string(), fields.collect(), r.size)
            })
            .collect();
        rust.sort();
        let mut table = table;
        table.sort();
        assert_eq!(table, rust);
    }

    #[test]
    fn parser_applies_std430_rules() {
        let g = parse_glsl("struct A { float a; vec3 b; uint c[2]; vec2 d; };");
        let (fields, size) = &g["A"];
        let offsets: Vec<usize> = fields.iter().map(|f| f.1).collect();
        assert_eq!(offsets, vec![0, 16, 28, 40]);
        assert_eq!(*size, 48);
    }

    /// Asserts that layout.glsl defines each `name` as `value` (`#define NAME 4u`).
    fn assert_glsl_defines(defines: &[(&str, u32)]) {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/scene/layout.glsl");
        let src = std::fs::read_to_string(path).expect("read layout.glsl");
        for (name, value) in defines {
            assert!(
                src.contains(&format!("#define {name} {value}u\n")),
                "{name} = {value} is not in layout.glsl"
            );
        }
    }

    #[test]
    fn emitter_kinds_match_glsl() {
        assert_glsl_defines(&[
            ("EMITTER_POINT", EMITTER_POINT),
            ("EMITTER_AREA", EMITTER_AREA),
            ("EMITTER_CONSTANT", EMITTER_CONSTANT),
            ("EMITTER_SPOT", EMITTER_SPOT),
            ("EMITTER_ENVMAP", EMITTER_ENVMAP),
            ("EMITTER_DIRECTIONAL", EMITTER_DIRECTIONAL),
            ("CAMERA_PERSPECTIVE", CAMERA_PERSPECTIVE),
            ("CAMERA_ORTHOGRAPHIC", CAMERA_ORTHOGRAPHIC),
            ("CAMERA_THINLENS", CAMERA_THINLENS),
            ("CAMERA_RADIANCEMETER", CAMERA_RADIANCEMETER),
            ("CAMERA_DISTANT", CAMERA_DISTANT),
            ("CAMERA_IRRADIANCEMETER", CAMERA_IRRADIANCEMETER),
            ("EMITTER_PROJECTOR", EMITTER_PROJECTOR),
            ("EMITTER_DIRECTIONAL_AREA", EMITTER_DIRECTIONAL_AREA),
            ("EMITTER_KIND_BIT_SPHERE_AREA", EMITTER_KIND_BIT_SPHERE_AREA),
            (
                "EMITTER_KIND_BIT_QUADRIC_AREA",
                EMITTER_KIND_BIT_QUADRIC_AREA,
            ),
            (
                "EMITTER_KIND_BIT_TEXTURE_SAMPLED",
                EMITTER_KIND_BIT_TEXTURE_SAMPLED,
            ),
            (
                "EMITTER_KIND_BIT_TEXTURE_SPHERE",
                EMITTER_KIND_BIT_TEXTURE_SPHERE,
            ),
        ]);
    }

    #[test]
    fn texture_kinds_and_features_match_glsl() {
        assert_glsl_defines(&[
            ("TEXTURE_BITMAP", TEXTURE_BITMAP),
            ("TEXTURE_CHECKERBOARD", TEXTURE_CHECKERBOARD),
            ("TEXTURE_NOISE", TEXTURE_NOISE),
            ("TEXTURE_MARBLE", TEXTURE_MARBLE),
            ("TEXTURE_CONSTANT", TEXTURE_CONSTANT),
            ("TEXTURE_MESH_ATTRIBUTE", TEXTURE_MESH_ATTRIBUTE),
            ("TEXTURE_ATTRIBUTE_FACE", TEXTURE_ATTRIBUTE_FACE),
            ("TEXTURE_NEAREST", TEXTURE_NEAREST),
            ("TEXTURE_WRAP_SHIFT", TEXTURE_WRAP_SHIFT),
            ("TEXTURE_WRAP_REPEAT", TEXTURE_WRAP_REPEAT),
            ("TEXTURE_WRAP_MIRROR", TEXTURE_WRAP_MIRROR),
            ("TEXTURE_WRAP_CLAMP", TEXTURE_WRAP_CLAMP),
            ("TEXTURE_FEATURE_BSDF", TEXTURE_FEATURE_BSDF),
            ("TEXTURE_FEATURE_NORMALMAP", TEXTURE_FEATURE_NORMALMAP),
            ("TEXTURE_FEATURE_ENVMAP", TEXTURE_FEATURE_ENVMAP),
            ("TEXTURE_FEATURE_AREA", TEXTURE_FEATURE_AREA),
            ("TEXTURE_FEATURE_LOOKUP_LOOP", TEXTURE_FEATURE_LOOKUP_LOOP),
            ("TEXTURE_FEATURE_TABLE", TEXTURE_FEATURE_TABLE),
            (
                "TEXTURE_FEATURE_EMITTER_PROFILE",
                TEXTURE_FEATURE_EMITTER_PROFILE,
            ),
            ("TEXTURE_FEATURE_PARAM_SHIFT", TEXTURE_FEATURE_PARAM_SHIFT),
        ]);
    }

    #[test]
    fn medium_and_surface_flags_match_glsl() {
        assert_glsl_defines(&[
            ("SURFACE_FEATURE_SPHERES", SURFACE_FEATURE_SPHERES),
            ("SURFACE_FEATURE_NORMALS", SURFACE_FEATURE_NORMALS),
            ("SURFACE_FEATURE_UVS", SURFACE_FEATURE_UVS),
            ("SURFACE_FEATURE_DISKS", SURFACE_FEATURE_DISKS),
            ("SURFACE_FEATURE_CYLINDERS", SURFACE_FEATURE_CYLINDERS),
            (
                "SURFACE_FEATURE_LINEAR_CURVES",
                SURFACE_FEATURE_LINEAR_CURVES,
            ),
            ("PRIM_TRIANGLE", PRIM_TRIANGLE),
            ("PRIM_SPHERE", PRIM_SPHERE),
            ("PRIM_DISK", PRIM_DISK),
            ("PRIM_CYLINDER", PRIM_CYLINDER),
            ("PRIM_INSTANCE", PRIM_INSTANCE),
            ("PRIM_INSTANCE_DATA", PRIM_INSTANCE_DATA),
            ("PRIM_SDFGRID", PRIM_SDFGRID),
            ("SURFACE_FEATURE_SDFGRIDS", SURFACE_FEATURE_SDFGRIDS),
            ("PRIM_LINEAR_CURVE", PRIM_LINEAR_CURVE),
            ("PRIM_BSPLINE_CURVE", PRIM_BSPLINE_CURVE),
            (
                "SURFACE_FEATURE_BSPLINE_CURVES",
                SURFACE_FEATURE_BSPLINE_CURVES,
            ),
            ("PRIM_ELLIPSOID", PRIM_ELLIPSOID),
            ("SURFACE_FEATURE_ELLIPSOIDS", SURFACE_FEATURE_ELLIPSOIDS),
            ("SHAPE_HAS_NORMALS", SHAPE_HAS_NORMALS),
            ("SHAPE_HAS_UVS", SHAPE_HAS_UVS),
            ("SHAPE_FLIP_NORMALS", SHAPE_FLIP_NORMALS),
            ("SHAPE_NULL_BSDF", SHAPE_NULL_BSDF),
            ("SHAPE_MEDIUM_TRANSITION", SHAPE_MEDIUM_TRANSITION),
            ("SHAPE_THIN_DIELECTRIC", SHAPE_THIN_DIELECTRIC),
            ("SHAPE_MIRRORED", SHAPE_MIRRORED),
            ("SHAPE_NORMALS_AGREE", SHAPE_NORMALS_AGREE),
            ("MEDIUM_HOMOGENEOUS", MEDIUM_HOMOGENEOUS),
            ("MEDIUM_GRID", MEDIUM_GRID),
            ("MEDIUM_SAMPLE_EMITTERS", MEDIUM_SAMPLE_EMITTERS),
            ("MEDIUM_ALBEDO_RGB", MEDIUM_ALBEDO_RGB),
            ("MEDIUM_DENSITY_PACKED", MEDIUM_DENSITY_PACKED),
            ("MEDIUM_FEATURE_HOMOGENEOUS", MEDIUM_FEATURE_HOMOGENEOUS),
            ("MEDIUM_FEATURE_PACKED1", MEDIUM_FEATURE_PACKED1),
            ("MEDIUM_FEATURE_PACKED3", MEDIUM_FEATURE_PACKED3),
            ("MEDIUM_FEATURE_DENSITY_WORDS", MEDIUM_FEATURE_DENSITY_WORDS),
            ("MEDIUM_FEATURE_WORDS1", MEDIUM_FEATURE_WORDS1),
            ("MEDIUM_FEATURE_WORDS3", MEDIUM_FEATURE_WORDS3),
            ("MEDIUM_FEATURE_ALBEDO_GRID", MEDIUM_FEATURE_ALBEDO_GRID),
            ("MEDIUM_FEATURE_GRIDS", MEDIUM_FEATURE_GRIDS),
        ]);
    }

    #[test]
    fn film_constants_match_glsl() {
        assert_glsl_defines(&[
            ("PATH_DELTA", PATH_DELTA),
            ("PATH_THIN_REFLECT", PATH_THIN_REFLECT),
            ("PATH_COVERED", PATH_COVERED),
            ("FILTER_BOX", FILTER_BOX),
            ("FILTER_TENT", FILTER_TENT),
            ("FILTER_GAUSSIAN", FILTER_GAUSSIAN),
            ("FILTER_MITCHELL", FILTER_MITCHELL),
            ("FILTER_LANCZOS", FILTER_LANCZOS),
            ("FILM_SAMPLE_VALID", FILM_SAMPLE_VALID),
            ("FILM_SAMPLE_COVERED", FILM_SAMPLE_COVERED),
        ]);
    }

    #[test]
    fn sampler_constants_match_glsl() {
        assert_glsl_defines(&[
            ("SAMPLER_INDEPENDENT", SAMPLER_INDEPENDENT),
            ("SAMPLER_STRATIFIED", SAMPLER_STRATIFIED),
            ("SAMPLER_MULTIJITTER", SAMPLER_MULTIJITTER),
            ("SAMPLER_ORTHOGONAL", SAMPLER_ORTHOGONAL),
            ("SAMPLER_LDSAMPLER", SAMPLER_LDSAMPLER),
            ("SAMPLER_ZSOBOL", SAMPLER_ZSOBOL),
            ("SAMPLER_SOBOL", SAMPLER_SOBOL),
            ("SAMPLER_PMJ02BN", SAMPLER_PMJ02BN),
            ("SAMPLER_ORTHOGONAL_BUSH", SAMPLER_ORTHOGONAL_BUSH),
            ("SAMPLER_JITTER", SAMPLER_JITTER),
            ("SAMPLER_STRENGTH_SHIFT", SAMPLER_STRENGTH_SHIFT),
            ("SAMPLER_SCRAMBLE_SHIFT", SAMPLER_SCRAMBLE_SHIFT),
            ("SAMPLER_SCRAMBLE_NONE", SAMPLER_SCRAMBLE_NONE),
            ("SAMPLER_SCRAMBLE_XOR", SAMPLER_SCRAMBLE_XOR),
            ("SAMPLER_SCRAMBLE_FAST_OWEN", SAMPLER_SCRAMBLE_FAST_OWEN),
            ("SAMPLER_SCRAMBLE_OWEN", SAMPLER_SCRAMBLE_OWEN),
        ]);
    }

    #[test]
    fn photon_flags_match_glsl() {
        assert_glsl_defines(&[("VISIBLE_POINT_NORMAL_MAP", VISIBLE_POINT_NORMAL_MAP)]);
    }

    #[test]
    fn bsdf_flags_match_glsl() {
        assert_glsl_defines(&[
            ("BSDF_TWOSIDED", BSDF_TWOSIDED),
            ("BSDF_NONLINEAR", BSDF_NONLINEAR),
            ("BSDF_NORMALMAP_FLIP", BSDF_NORMALMAP_FLIP),
            ("BSDF_NORMALMAP_SHADOWING", BSDF_NORMALMAP_SHADOWING),
            ("BSDF_TABLE_TEXTURES", BSDF_TABLE_TEXTURES),
        ]);
    }

    #[test]
    fn workgroup_size_matches_glsl() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/queue/wavefront.glsl");
        let src = std::fs::read_to_string(path).expect("read wavefront.glsl");
        assert!(src.contains(&format!("#define WORKGROUP_SIZE {WORKGROUP_SIZE}\n")));
    }
}

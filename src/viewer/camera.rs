//! The viewer's camera: the scene's camera moved, turned, orbited and zoomed by the
//! controls, as a camera-to-world transform and field of view for the renderer.
//!
//! Directions follow the image, whatever the scene's `to_world` holds (scale, or the
//! mirror Mitsuba scenes often have): "right" is the world direction of the image's
//! +x, "up" of its -y (image rows grow downwards), "forward" the view direction.
//! Turning is a yaw about the scene camera's up and a pitch about its right axis,
//! both measured from the scene camera, so turning back and forth returns exactly.

use glam::{Mat3, Mat4, Quat, Vec3};

use crate::scene::Scene;

/// Most pitch above or below the scene camera's view, in degrees (at 90 the yaw
/// axis and the view would line up).
const MAX_PITCH_DEG: f32 = 89.0;
/// The narrowest and widest horizontal fields of view, in degrees.
const FOV_RANGE_DEG: (f32, f32) = (1.0, 160.0);

/// The scene camera as the controls left it.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraRig {
    /// The scene's camera: its position, its linear part (rotation with any scale or
    /// mirror) and its field of view.
    home_position: Vec3,
    linear: Mat3,
    home_fov_deg: f32,
    /// World directions of the scene camera's view: forward, right, up (unit).
    forward0: Vec3,
    right0: Vec3,
    up0: Vec3,
    /// Distance from the camera to the point it orbits, along its view.
    pivot_distance: f32,
    /// How far a move key moves, in scene units (the scene's size / 100 at first).
    home_speed: f32,
    pub position: Vec3,
    /// Radians about `up0` (positive turns right) and about the right axis
    /// (positive looks up).
    pub yaw: f32,
    pub pitch: f32,
    pub fov_deg: f32,
    pub speed: f32,
}

/// The bounding sphere of a scene's shapes (a unit sphere at the origin if empty):
/// centre and radius.
pub fn scene_bounds(scene: &Scene) -> (Vec3, f32) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for m in &scene.meshes {
        for p in &m.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
    }
    for q in &scene.quadrics {
        let (a, b) = q.bounds();
        lo = lo.min(a);
        hi = hi.max(b);
    }
    if !(lo.is_finite() && hi.is_finite()) || lo.cmpgt(hi).any() {
        return (Vec3::ZERO, 1.0);
    }
    ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-6))
}

impl CameraRig {
    /// The rig of a camera at `to_world` with a horizontal field of view of `fov_deg`,
    /// in a scene whose bounding sphere is `bounds` (centre, radius): the camera
    /// orbits the point of its view nearest the centre, and moves by 1/100 of the
    /// scene's diameter a key press.
    pub fn new(to_world: Mat4, fov_deg: f32, bounds: (Vec3, f32)) -> CameraRig {
        let linear = Mat3::from_mat4(to_world);
        let position = to_world.w_axis.truncate();
        // Camera space: +z views, +y is up, +x is the image's left (column 0).
        let unit = |v: Vec3, fallback: Vec3| v.try_normalize().unwrap_or(fallback);
        let forward0 = unit(linear * Vec3::Z, Vec3::Z);
        let right0 = unit(linear * -Vec3::X, Vec3::X);
        let up0 = unit(linear * Vec3::Y, Vec3::Y);
        let (centre, radius) = bounds;
        let along = (centre - position).dot(forward0);
        let pivot_distance = if along > 1e-3 * radius {
            along
        } else {
            (centre - position).length().max(radius)
        };
        let home_speed = radius * 2.0 / 100.0;
        CameraRig {
            home_position: position,
            linear,
            home_fov_deg: fov_deg,
            forward0,
            right0,
            up0,
            pivot_distance,
            home_speed,
            position,
            yaw: 0.0,
            pitch: 0.0,
            fov_deg,
            speed: home_speed,
        }
    }

    /// The rig of a scene's camera.
    pub fn of_scene(scene: &Scene) -> CameraRig {
        CameraRig::new(
            scene.camera.to_world,
            scene.camera.fov_x_deg,
            scene_bounds(scene),
        )
    }

    /// The rotation from the scene camera's orientation to this one: the pitch about
    /// the scene camera's right axis, then the yaw about its up axis.
    fn rotation(&self) -> Quat {
        // Rotating v about a by a positive angle turns it towards a x v: the yaw axis
        // turns forward towards right, the pitch axis turns forward towards up.
        let yaw_axis = self.forward0.cross(self.right0).normalize_or_zero();
        let pitch_axis = self.forward0.cross(self.up0).normalize_or_zero();
        Quat::from_axis_angle(yaw_axis, self.yaw) * Quat::from_axis_angle(pitch_axis, self.pitch)
    }

    pub fn forward(&self) -> Vec3 {
        self.rotation() * self.forward0
    }

    pub fn right(&self) -> Vec3 {
        self.rotation() * self.right0
    }

    pub fn up(&self) -> Vec3 {
        self.rotation() * self.up0
    }

    /// Camera to world, for the renderer.
    pub fn to_world(&self) -> Mat4 {
        let linear = Mat3::from_quat(self.rotation()) * self.linear;
        let mut m = Mat4::from_mat3(linear);
        m.w_axis = self.position.extend(1.0);
        m
    }

    /// Moves by `steps` move steps along right, up and forward.
    pub fn translate(&mut self, steps: Vec3) {
        self.position +=
            (self.right() * steps.x + self.up() * steps.y + self.forward() * steps.z) * self.speed;
    }

    /// Turns in place by `yaw_deg` (right) and `pitch_deg` (up).
    pub fn turn(&mut self, yaw_deg: f32, pitch_deg: f32) {
        self.yaw += yaw_deg.to_radians();
        self.pitch = (self.pitch + pitch_deg.to_radians())
            .clamp(-MAX_PITCH_DEG.to_radians(), MAX_PITCH_DEG.to_radians());
    }

    /// Orbits the point `pivot_distance` ahead by `yaw_deg` and `pitch_deg`, still
    /// looking at it.
    pub fn orbit(&mut self, yaw_deg: f32, pitch_deg: f32) {
        let pivot = self.position + self.forward() * self.pivot_distance;
        self.turn(yaw_deg, pitch_deg);
        self.position = pivot - self.forward() * self.pivot_distance;
    }

    /// Narrows (`clicks` > 0) or widens the field of view by 10% a click.
    pub fn zoom(&mut self, clicks: f32) {
        self.fov_deg =
            (self.fov_deg * 1.1f32.powf(-clicks)).clamp(FOV_RANGE_DEG.0, FOV_RANGE_DEG.1);
    }

    /// Multiplies the move step by `factor`.
    pub fn scale_speed(&mut self, factor: f32) {
        self.speed = (self.speed * factor).clamp(self.home_speed * 1e-6, self.home_speed * 1e6);
    }

    /// Back to the scene's camera (and move step).
    pub fn reset(&mut self) {
        self.position = self.home_position;
        self.yaw = 0.0;
        self.pitch = 0.0;
        self.fov_deg = self.home_fov_deg;
        self.speed = self.home_speed;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    /// Mitsuba's look-at from (0, 0, 5) to the origin with +y up, and the same with
    /// the x mirror Mitsuba scenes often add (`<scale x="-1"/>`).
    fn rigs() -> Vec<CameraRig> {
        let look = Mat4::look_at_rh(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y).inverse();
        // look_at_rh views down -z; wavetrace's camera views down +z with +x left:
        // turn it half a turn about y.
        let m = look * Mat4::from_rotation_y(std::f32::consts::PI);
        let mirrored = m * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let bounds = (Vec3::ZERO, 1.0);
        vec![
            CameraRig::new(m, 40.0, bounds),
            CameraRig::new(mirrored, 40.0, bounds),
        ]
    }

    #[test]
    fn directions_follow_the_image() {
        for rig in rigs() {
            assert!(close(rig.forward(), -Vec3::Z));
            assert!(close(rig.up(), Vec3::Y));
            // The image's right, seen from +z looking at the origin, is +x.
            let m = rig.to_world();
            let right = (Mat3::from_mat4(m) * -Vec3::X).normalize();
            assert!(close(rig.right(), right));
            assert!(close(
                rig.to_world().w_axis.truncate(),
                Vec3::new(0.0, 0.0, 5.0)
            ));
        }
        // Unmirrored, the image's right is +x; mirrored, it is -x (the scene's own
        // camera shows it mirrored, and the viewer keeps what the scene shows).
        let r = rigs();
        assert!(close(r[0].right(), Vec3::X));
        assert!(close(r[1].right(), -Vec3::X));
    }

    #[test]
    fn turning_moves_the_view_the_named_way_and_back() {
        for mut rig in rigs() {
            let home = rig.clone();
            let right = rig.right();
            rig.turn(10.0, 0.0);
            assert!(rig.forward().dot(right) > 0.17, "yaw turns right");
            rig.turn(0.0, 10.0);
            assert!(rig.forward().dot(home.up()) > 0.17, "pitch looks up");
            rig.turn(-10.0, -10.0);
            assert!(close(rig.forward(), home.forward()));
            rig.turn(0.0, 200.0);
            assert!(rig.pitch.to_degrees() <= MAX_PITCH_DEG + 1e-3);
        }
    }

    #[test]
    fn moves_follow_the_view_and_orbit_keeps_the_pivot() {
        for mut rig in rigs() {
            let step = rig.speed;
            let p0 = rig.position;
            rig.translate(Vec3::new(0.0, 0.0, 1.0));
            assert!(close(rig.position, p0 + rig.forward() * step));
            rig.reset();
            // The pivot is the scene's centre, 5 units ahead.
            rig.orbit(90.0, 0.0);
            assert!(close(rig.position + rig.forward() * 5.0, Vec3::ZERO));
            assert!((rig.position.length() - 5.0).abs() < 1e-4);
            assert!(
                rig.position.z.abs() < 1e-4,
                "a quarter turn about the pivot"
            );
            rig.reset();
            assert!(close(rig.position, p0));
        }
    }

    #[test]
    fn zoom_and_speed_stay_in_range() {
        let mut rig = rigs().remove(0);
        rig.zoom(1.0);
        assert!((rig.fov_deg - 40.0 / 1.1).abs() < 1e-4);
        rig.zoom(-1000.0);
        assert_eq!(rig.fov_deg, FOV_RANGE_DEG.1);
        let s = rig.speed;
        rig.scale_speed(2.0);
        assert_eq!(rig.speed, 2.0 * s);
        rig.reset();
        assert_eq!((rig.fov_deg, rig.speed), (40.0, s));
    }
}

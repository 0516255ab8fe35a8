//! The camera along a run's path: spread over the whole path, or flown at `--speed` from
//! its start.

use render_core::geom::Camera;
use render_core::scene::CameraPath;

use super::RunOptions;

/// How far the camera flies at `--speed`: the metres a frame and the metres the measured
/// frames cover, which must stay within the path (a camera held at its end would count as a
/// still one).
pub(crate) fn pace(path: &CameraPath, options: &RunOptions) -> anyhow::Result<Option<(f32, f32)>> {
    let Some(speed) = options.speed_m_per_s else {
        return Ok(None);
    };
    let per_frame = speed / 30.0;
    let flown = per_frame * (options.frames.max(1) - 1) as f32;
    let length = path.length_m();
    anyhow::ensure!(
        flown <= length * (1.0 + 1e-4),
        "--speed {speed} flies {flown:.0} m in {} frames (1/30 s each), past the end of path '{}' \
         ({length:.0} m): give fewer frames or a lower speed",
        options.frames.max(1),
        path.name,
    );
    Ok(Some((per_frame, flown)))
}

/// Frame `frame` of a run along `path` (the warm-up frames at its start), with `template`'s
/// lens and up.
pub(crate) fn camera_at(
    path: &CameraPath,
    template: &Camera,
    (frame, options): (u32, &RunOptions),
) -> Camera {
    let measured = frame.saturating_sub(options.warmup);
    let key = match options.speed_m_per_s {
        Some(speed) => path.sample_at_distance(speed * measured as f32 / 30.0),
        None => path.sample(measured as f32 / (options.frames.max(2) - 1) as f32),
    };
    Camera::look_at(
        key.eye,
        key.target,
        template.fov_y_rad,
        template.near_m,
        template.far_m,
    )
    .with_up(template.world_up)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_paced_run_flies_equal_metres_a_frame_from_the_start_and_stays_on_the_path() {
        let path = CameraPath::city_streets(&render_core::scene::CityParams::small(0));
        let lens = Camera::look_at(glam::Vec3::ZERO, glam::Vec3::X, 0.9, 0.1, 500.0);
        let options = RunOptions {
            frames: 31,
            warmup: 2,
            animate: false,
            time: 0.0,
            no_truth: true,
            flicker: false,
            moving_sun_deg_per_s: 0.0,
            speed_m_per_s: Some(15.0),
        };
        let eye = |frame| camera_at(&path, &lens, (frame, &options)).eye;
        let start = path.keys()[0].eye;
        // The warm-up frames wait at the start; then half a metre a frame along the street.
        assert_eq!(eye(0), start);
        assert_eq!(eye(2), start);
        for frame in 3..33 {
            let flown = 0.5 * (frame - 2) as f32;
            assert!(
                (eye(frame).distance(start) - flown).abs() < 1e-3,
                "frame {frame}"
            );
        }
        assert_eq!(pace(&path, &options).unwrap(), Some((0.5, 15.0)));
        // Without a speed the frames spread over the whole path.
        let spread = RunOptions {
            speed_m_per_s: None,
            ..options
        };
        assert_eq!(pace(&path, &spread).unwrap(), None);
        assert_eq!(
            camera_at(&path, &lens, (32, &spread)).eye,
            path.keys().last().unwrap().eye
        );
        // A speed that would fly past the path's end is refused, naming both distances.
        let length = path.length_m();
        let too_fast = RunOptions {
            speed_m_per_s: Some(2.0 * length),
            ..options
        };
        let error = pace(&path, &too_fast).unwrap_err().to_string();
        assert!(
            error.contains("past the end of path 'city streets'")
                && error.contains(&format!("({length:.0} m)")),
            "{error}"
        );
    }
}

//! Off-screen render tests: golden images and numbers read off frames.
//!
//! These need a graphics adapter; `scripts/test` installs Mesa's software
//! Vulkan driver. Without an adapter they fail with the error that names the
//! packages; they never skip.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]
#![cfg(feature = "render")]

use std::path::PathBuf;

use glam::{Quat, Vec2, Vec3};
use tickwork_engine::render::{
    Blend, Camera, FrameView, GoldenImages, Interpolation, Line, OFFSCREEN_FORMAT, OffscreenTarget, Renderer,
    RendererConfig, RgbaImage, Trails,
};
use tickwork_engine::{FixedClock, Gravity, Particle, RigidBody, Scene, World};

use crate::support::gpu;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn golden() -> GoldenImages {
    GoldenImages::new(root().join("assets/golden"), root().join("target/golden"))
}

fn render(world: &World, alpha: f32, camera: Camera, width: u32, height: u32, config: RendererConfig) -> RgbaImage {
    crate::support::draw(&FrameView::new(world, alpha, camera), config, (width, height))
}

fn check(name: &str, image: &RgbaImage) {
    if let Err(error) = golden().check(name, image) {
        panic!("{error}");
    }
}

/// A 2D camera showing x in [-8, 8], y in [-4.5, 4.5] at 16:9.
fn camera_2d() -> Camera {
    Camera::TwoD {
        center: Vec2::ZERO,
        height: 9.0,
    }
}

/// Twelve particles: four sizes by three colours, one translucent.
fn layout() -> World {
    let mut world = World::default();
    let colours = [[230, 60, 50, 255], [60, 200, 90, 255], [70, 120, 240, 160]];
    for (i, radius) in [0.1_f32, 0.3, 0.6, 1.0].into_iter().enumerate() {
        for (j, colour) in colours.into_iter().enumerate() {
            world
                .spawn(Particle {
                    position: Vec3::new(-6.0 + 4.0 * i as f32, 2.5 - 2.5 * j as f32, 0.0),
                    radius,
                    colour,
                    ..Particle::default()
                })
                .expect("spawn");
        }
    }
    world
}

#[test]
fn particle_layout_matches_its_golden_image() {
    check(
        "layout",
        &render(&layout(), 0.0, camera_2d(), 320, 180, RendererConfig::default()),
    );
}

/// Particles moving in different directions, stepped once at 10 Hz.
fn moving() -> (World, Vec<(Vec3, Vec3)>) {
    let mut world = World::default();
    let mut ends = Vec::new();
    for k in 0..8 {
        let angle = k as f32 * std::f32::consts::TAU / 8.0;
        let start = Vec3::new(2.0 * angle.cos(), 2.0 * angle.sin(), 0.0);
        let velocity = Vec3::new(-angle.sin(), angle.cos(), 0.0) * 20.0; // 2 m per step
        world
            .spawn(Particle {
                position: start,
                velocity,
                radius: 0.35,
                colour: [255, 200 - 20 * k as u8, 40 + 25 * k as u8, 255],
                ..Particle::default()
            })
            .expect("spawn");
        ends.push((start, start + velocity * 0.1));
    }
    let mut clock = FixedClock::new(tickwork_engine::ClockConfig {
        rate: tickwork_engine::Rate::hz(10).expect("rate"),
        ..Default::default()
    })
    .expect("clock");
    for step in clock.step(1).fixed_steps() {
        world.step(step).expect("step");
    }
    (world, ends)
}

#[test]
fn a_frame_at_alpha_half_shows_the_midpoint_state() {
    let (world, ends) = moving();
    let between = render(&world, 0.5, camera_2d(), 320, 180, RendererConfig::default());
    let mut midpoint = World::default();
    for (row, (start, end)) in ends.iter().enumerate() {
        midpoint
            .spawn(Particle {
                position: 0.5 * (*start + *end),
                radius: 0.35,
                colour: world.particles().colour[row],
                ..Particle::default()
            })
            .expect("spawn");
    }
    let expected = render(&midpoint, 0.0, camera_2d(), 320, 180, RendererConfig::default());
    let comparison = tickwork_engine::render::compare(&between, &expected, Default::default()).expect("same size");
    assert!(
        comparison.differing == 0 && comparison.max_channel_difference <= 2,
        "the interpolated frame differs from the midpoint state's frame: {comparison:?}"
    );
    check("interpolation_half", &between);
    // And the two ends are different pictures (the test can fail).
    let at_start = render(&world, 0.0, camera_2d(), 320, 180, RendererConfig::default());
    let differing = tickwork_engine::render::compare(&at_start, &between, Default::default()).expect("size");
    assert!(
        differing.differing > 500,
        "alpha 0 and 0.5 should differ: {differing:?}"
    );
}

#[test]
fn extrapolation_and_no_interpolation_place_particles_where_they_say() {
    let (world, ends) = moving();
    let config = |interpolation| RendererConfig {
        interpolation,
        ..RendererConfig::default()
    };
    // Extrapolating at alpha 0.5 puts particles 1.5 steps from the start.
    let extrapolated = render(&world, 0.5, camera_2d(), 320, 180, config(Interpolation::Extrapolate));
    let current = render(&world, 0.5, camera_2d(), 320, 180, config(Interpolation::None));
    let (start, end) = ends[0];
    let beyond = start + 1.5 * (end - start);
    let pixel = |p: Vec3| (160.0 + p.x * 20.0, 90.0 - p.y * 20.0);
    let lit = |image: &RgbaImage, p: Vec3| {
        let (x, y) = pixel(p);
        image.get_pixel(x as u32, y as u32).0[0] > 128
    };
    assert!(lit(&extrapolated, beyond) && !lit(&extrapolated, end));
    assert!(lit(&current, end) && !lit(&current, beyond));
}

#[test]
fn a_teleported_particle_is_not_smeared_between_places() {
    let (mut world, ends) = moving();
    let entity = world.entities().rows()[0];
    world.teleport(entity, Vec3::new(-6.0, -3.0, 0.0)).expect("teleport");
    let image = render(&world, 0.5, camera_2d(), 320, 180, RendererConfig::default());
    let (start, end) = ends[0];
    let mid = 0.5 * (start + end);
    let at = |p: Vec3| {
        image
            .get_pixel((160.0 + p.x * 20.0) as u32, (90.0 - p.y * 20.0) as u32)
            .0
    };
    assert!(at(Vec3::new(-6.0, -3.0, 0.0))[0] > 128, "drawn where it was teleported");
    assert!(at(mid)[0] < 40, "not drawn half-way: {:?}", at(mid));
}

#[test]
fn odd_widths_are_read_back_without_row_padding() {
    // 301 x 4 bytes is not a multiple of 256: rows are padded in the copy.
    let mut world = World::default();
    world
        .spawn(Particle {
            position: Vec3::new(3.0, 2.0, 0.0),
            radius: 0.2,
            colour: [255, 255, 255, 255],
            ..Particle::default()
        })
        .expect("spawn");
    let camera = Camera::TwoD {
        center: Vec2::ZERO,
        height: 10.0,
    };
    let image = render(&world, 0.0, camera, 301, 157, RendererConfig::default());
    assert_eq!(image.dimensions(), (301, 157));
    // 15.7 px per metre; (3, 2) is at (150.5 + 47.1, 78.5 - 31.4) in
    // pixel-edge coordinates, so the centroid of pixel centres is there too.
    let (mut sx, mut sy, mut sw) = (0.0, 0.0, 0.0);
    for (x, y, p) in image.enumerate_pixels() {
        let w = f64::from(p.0[0].saturating_sub(20));
        sx += w * (f64::from(x) + 0.5);
        sy += w * (f64::from(y) + 0.5);
        sw += w;
    }
    let centroid = (sx / sw, sy / sw);
    assert!(
        (centroid.0 - 197.6).abs() < 0.3 && (centroid.1 - 47.1).abs() < 0.3,
        "particle drawn at {centroid:?}, expected (197.6, 47.1)"
    );
    let lit = image.pixels().filter(|p| p.0[0] > 128).count();
    // A disc of radius 3.14 px: about 31 pixels.
    assert!((20..=45).contains(&lit), "{lit} lit pixels");
    check(
        "odd_size",
        &render(&layout(), 0.0, camera_2d(), 301, 157, RendererConfig::default()),
    );
}

#[test]
fn colours_are_srgb_and_blending_is_linear() {
    let mut world = World::default();
    world
        .spawn(Particle {
            radius: 3.0,
            colour: [128, 64, 200, 255],
            ..Particle::default()
        })
        .expect("spawn");
    let config = RendererConfig {
        background: [0, 0, 0, 255],
        ..RendererConfig::default()
    };
    let image = render(&world, 0.0, Camera::default(), 64, 64, config.clone());
    assert_eq!(
        image.get_pixel(32, 32).0,
        [128, 64, 200, 255],
        "an opaque colour comes out as given"
    );
    // Half-transparent white over black: 50% linear light is sRGB 188, not 128.
    world.particles_mut().colour[0] = [255, 255, 255, 128];
    let image = render(&world, 0.0, Camera::default(), 64, 64, config.clone());
    let v = image.get_pixel(32, 32).0[0];
    assert!(v.abs_diff(188) <= 2, "got {v}");
    // Additive: two overlapping half-bright particles sum in linear light.
    world.particles_mut().colour[0] = [188, 188, 188, 255];
    world
        .spawn(Particle {
            radius: 3.0,
            colour: [188, 188, 188, 255],
            ..Particle::default()
        })
        .expect("spawn");
    let additive = RendererConfig {
        blend: Blend::Additive,
        ..config
    };
    let image = render(&world, 0.0, Camera::default(), 64, 64, additive);
    assert!(image.get_pixel(32, 32).0[0] >= 254, "{:?}", image.get_pixel(32, 32));
}

#[test]
fn trails_and_lines_match_their_golden_image() {
    let mut world = World::default();
    world.add_force(Gravity::EARTH);
    let ball = world
        .spawn(Particle {
            position: Vec3::new(-7.0, -3.0, 0.0),
            velocity: Vec3::new(5.0, 10.0, 0.0),
            radius: 0.2,
            colour: [250, 210, 60, 255],
            ..Particle::default()
        })
        .expect("spawn");
    let mut trails = Trails::new(200);
    trails.follow(ball, [250, 210, 60, 255]);
    let mut clock = FixedClock::default();
    for step in clock.step(100).fixed_steps() {
        world.step(step).expect("step");
        trails.record(&world);
    }
    let ground = [Line {
        a: Vec3::new(-8.0, -3.2, 0.0),
        b: Vec3::new(8.0, -3.2, 0.0),
        colour: [120, 200, 255, 255],
    }];
    let view = FrameView {
        trails: Some(&trails),
        lines: &ground,
        ..FrameView::new(&world, 0.5, camera_2d())
    };
    let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, RendererConfig::default()).expect("renderer");
    let target = OffscreenTarget::new(gpu(), 320, 180, 4).expect("target");
    let image = target.render(gpu(), &mut renderer, &view).expect("frame");
    // The apex of the parabola (t = 1.02 s, y = 2.1) is on the trail.
    let apex = (
        160.0 + (-7.0 + 5.0 * 10.0 / 9.81) * 20.0,
        90.0 - (-3.0 + 100.0 / (2.0 * 9.81)) * 20.0,
    );
    let near_apex = (-2..=2)
        .flat_map(|dx| (-2..=2).map(move |dy| (dx, dy)))
        .any(|(dx, dy)| {
            image
                .get_pixel((apex.0 as i32 + dx) as u32, (apex.1 as i32 + dy) as u32)
                .0[0]
                > 60
        });
    assert!(near_apex, "no trail near the apex {apex:?}");
    check("trails", &image);
}

#[test]
fn rigid_body_orientation_is_visible() {
    let mut world = World::default();
    let body = |angle: f32, x: f32| {
        let mut body = RigidBody::solid_box(1.0, Vec3::new(1.2, 0.5, 0.3));
        body.orientation = Quat::from_rotation_z(angle.to_radians());
        body.particle.position = Vec3::new(x, 0.0, 0.0);
        body.particle.colour = [220, 220, 220, 255];
        body
    };
    world.spawn_rigid(body(0.0, -4.0)).expect("spawn");
    world.spawn_rigid(body(45.0, 0.0)).expect("spawn");
    world.spawn_rigid(body(90.0, 4.0)).expect("spawn");
    let image = render(&world, 0.0, camera_2d(), 320, 180, RendererConfig::default());
    // The red x axis of the 90-degree box points up: red above its centre.
    let red_above = (1..40).any(|dy| {
        let p = image.get_pixel(160 + 80, 90 - dy).0;
        p[0] > 120 && p[1] < 110
    });
    assert!(red_above, "the turned box's x axis should point up");
    check("rigid_bodies", &image);
    // The same scene from a 3D orbit camera.
    let orbit = Camera::Orbit {
        target: Vec3::ZERO,
        distance: 14.0,
        yaw: 30.0,
        pitch: 25.0,
        fov_y: 45.0,
    };
    check(
        "rigid_bodies_3d",
        &render(&world, 0.0, orbit, 320, 180, RendererConfig::default()),
    );
}

#[test]
fn hud_text_matches_its_golden_image() {
    let world = layout();
    let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, RendererConfig::default()).expect("renderer");
    let target = OffscreenTarget::new(gpu(), 320, 180, 4).expect("target");
    let view = FrameView {
        hud: "fps 60 | steps 1\nrk4 | 12 particles",
        ..FrameView::new(&world, 0.0, camera_2d())
    };
    let image = target.render(gpu(), &mut renderer, &view).expect("frame");
    // Text pixels are light grey in the top-left corner where no particle is.
    let text = (0..60)
        .flat_map(|y| (0..110).map(move |x| (x, y)))
        .filter(|&(x, y)| image.get_pixel(x, y).0[0] > 150);
    assert!(text.count() > 100, "no HUD text drawn");
    check("hud", &image);
}

#[test]
fn scene_files_render_through_their_camera_hints() {
    let scene = Scene::load(&root().join("assets/scenes/tops.ron")).expect("scene");
    let (world, _) = scene.build().expect("build");
    let camera = Camera::from_hint(&scene.spec.camera);
    check(
        "tops_scene",
        &render(&world, 0.0, camera, 320, 180, RendererConfig::default()),
    );
}

#[test]
fn bad_sizes_and_settings_are_errors() {
    let error = OffscreenTarget::new(gpu(), 0, 100, 4).expect_err("zero width");
    assert!(error.to_string().starts_with("cannot render a 0x100 image"), "{error}");
    let error = Renderer::new(
        gpu(),
        OFFSCREEN_FORMAT,
        RendererConfig {
            samples: 2,
            ..RendererConfig::default()
        },
    )
    .expect_err("samples");
    assert_eq!(error.to_string(), "renderer: samples must be 1 or 4, got 2");
    let world = layout();
    let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, RendererConfig::default()).expect("renderer");
    let target = OffscreenTarget::new(gpu(), 32, 32, 4).expect("target");
    let error = target
        .render(
            gpu(),
            &mut renderer,
            &FrameView::new(&world, f32::NAN, Camera::default()),
        )
        .expect_err("NaN alpha");
    assert_eq!(error.to_string(), "renderer: alpha must be finite, got NaN");
}

#[test]
fn the_splat_path_draws_what_the_quads_draw() {
    // 3000 small particles in 2D: drawn as quads, then by the compute splat.
    let world = small_lattice();
    let quads = render(&world, 0.0, camera_2d(), 320, 180, quads_only());
    let splat_config = RendererConfig {
        splat_threshold: Some(0),
        ..RendererConfig::default()
    };
    let splat = render(&world, 0.0, camera_2d(), 320, 180, splat_config);
    let tolerance = tickwork_engine::render::Tolerance {
        channel: 40,
        max_fraction: 0.02,
    };
    let comparison = tickwork_engine::render::compare(&splat, &quads, tolerance).expect("size");
    assert!(comparison.fraction() <= tolerance.max_fraction, "{comparison:?}");
    let lit = splat.pixels().filter(|p| p.0[2] > 100).count();
    assert!(lit > 3000, "the splat drew {lit} pixels");
    // Additive blending through the splat sums like additive quads.
    let additive = |splat_threshold| RendererConfig {
        blend: Blend::Additive,
        splat_threshold,
        ..RendererConfig::default()
    };
    let quads = render(&world, 0.0, camera_2d(), 320, 180, additive(Some(usize::MAX)));
    let splat = render(&world, 0.0, camera_2d(), 320, 180, additive(Some(0)));
    let comparison = tickwork_engine::render::compare(&splat, &quads, tolerance).expect("size");
    assert!(
        comparison.fraction() <= tolerance.max_fraction,
        "additive: {comparison:?}"
    );
}

#[test]
fn overlapping_additive_splats_sum_exactly() {
    // Two half-bright particles on the same spot: 2 x linear(188) = 1.0.
    let mut world = World::default();
    for _ in 0..2 {
        world
            .spawn(Particle {
                radius: 0.3,
                colour: [188, 188, 188, 255],
                ..Particle::default()
            })
            .expect("spawn");
    }
    let config = RendererConfig {
        blend: Blend::Additive,
        splat_threshold: Some(0),
        background: [0, 0, 0, 255],
        ..RendererConfig::default()
    };
    let image = render(&world, 0.0, Camera::default(), 64, 64, config);
    assert!(image.get_pixel(32, 32).0[0] >= 254, "{:?}", image.get_pixel(32, 32));
    assert_eq!(image.get_pixel(2, 2).0, [0, 0, 0, 255]);
}

#[test]
fn springs_are_drawn_between_their_ends() {
    let scene = Scene::load(&root().join("assets/scenes/pendulum_chain.ron")).expect("scene");
    let (mut world, entities) = scene.build().expect("build");
    let mut clock = FixedClock::new(tickwork_engine::ClockConfig {
        rate: scene.rate().expect("rate"),
        ..Default::default()
    })
    .expect("clock");
    for step in clock.step(60).fixed_steps() {
        world.step(step).expect("step");
    }
    let camera = Camera::from_hint(&scene.spec.camera);
    let image = render(&world, 0.0, camera, 320, 180, RendererConfig::default());
    // Half-way between the anchor (0, 0) and the first mass, the spring's
    // grey line is drawn.
    let first = world.position(entities[0]).expect("alive");
    let matrices = camera.matrices(320, 180);
    let mid = matrices.view_proj.project_point3(0.5 * first);
    let (x, y) = ((mid.x + 1.0) * 160.0, (1.0 - mid.y) * 90.0);
    let near = (-1..=1)
        .flat_map(|dx| (-1..=1).map(move |dy| (dx, dy)))
        .any(|(dx, dy)| {
            let p = image.get_pixel((x as i32 + dx) as u32, (y as i32 + dy) as u32).0;
            p[0] > 60 && p[2] > 60
        });
    assert!(near, "no spring line near ({x}, {y})");
    check("springs", &image);
}

/// One anti-aliased quad per particle, whatever the count.
fn quads_only() -> RendererConfig {
    RendererConfig {
        splat_threshold: Some(usize::MAX),
        ..RendererConfig::default()
    }
}

/// 3000 small particles on a lattice, for the splat tests.
fn small_lattice() -> World {
    let mut world = World::default();
    for k in 0..3000u32 {
        let (i, j) = (k % 75, k / 75);
        world
            .spawn(Particle {
                position: Vec3::new(-7.4 + 0.2 * i as f32, -4.0 + 0.2 * j as f32, 0.0),
                radius: 0.035 + 0.01 * (k % 3) as f32,
                colour: [(k * 7 % 256) as u8, (k * 13 % 256) as u8, 200, 255],
                ..Particle::default()
            })
            .expect("spawn");
    }
    world
}

#[test]
fn the_splat_resolves_odd_widths_and_composites_into_targets_that_refuse_copies() {
    let world = small_lattice();
    let splat = RendererConfig {
        splat_threshold: Some(0),
        ..RendererConfig::default()
    };
    let tolerance = tickwork_engine::render::Tolerance {
        channel: 40,
        max_fraction: 0.02,
    };
    // Odd width: the resolved rows are padded to 256 bytes before the copy.
    let quads = render(&world, 0.0, camera_2d(), 301, 157, quads_only());
    let resolved = render(&world, 0.0, camera_2d(), 301, 157, splat.clone());
    let comparison = tickwork_engine::render::compare(&resolved, &quads, tolerance).expect("size");
    assert!(
        comparison.fraction() <= tolerance.max_fraction,
        "odd width: {comparison:?}"
    );

    // A texture without COPY_DST (as some window surfaces): the splat is
    // composited by a full-screen pass instead of copied in.
    let (width, height) = (320, 180);
    let texture = gpu().device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: OFFSCREEN_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let buffers =
        tickwork_engine::render::FrameBuffers::new(gpu(), width, height, OFFSCREEN_FORMAT, 4).expect("buffers");
    let mut renderer = Renderer::new(gpu(), OFFSCREEN_FORMAT, splat).expect("renderer");
    renderer
        .prepare(gpu(), &buffers, &FrameView::new(&world, 0.0, camera_2d()))
        .expect("prepare");
    let readback = gpu().device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: u64::from(width * 4 * height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu().device.create_command_encoder(&Default::default());
    renderer.encode(&mut encoder, &buffers, &view);
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * 4), // 1280: already a multiple of 256
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    gpu().queue.submit(Some(encoder.finish()));
    readback.slice(..).map_async(wgpu::MapMode::Read, |r| r.expect("map"));
    gpu().device.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
    let pixels = readback.slice(..).get_mapped_range().expect("mapped").to_vec();
    let composited = RgbaImage::from_raw(width, height, pixels).expect("size");
    let quads = render(&world, 0.0, camera_2d(), width, height, quads_only());
    let comparison = tickwork_engine::render::compare(&composited, &quads, tolerance).expect("size");
    assert!(
        comparison.fraction() <= tolerance.max_fraction,
        "composited: {comparison:?}"
    );
}

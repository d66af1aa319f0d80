//! Pictures of runs: `sph render` (particle frames, the paper's Figs. 2–3), `sph plot` (charts
//! of the CSV logs, Fig. 4) and `sph bench --plot`'s chart (Fig. 5).
//!
//! Runs are tiny real simulations (coarse shipped scenes, a few hundredths of a second) in
//! scratch folders. The golden tests draw synthetic frames built in code and compare them with
//! `tests/golden/*.png`; `SPH_BLESS=1` writes those files (commit them, and say why).

use crate::common::run::SPH as BIN;
use crate::common::scratch_dir as scratch;
use sph::bench::{BenchRow, timing_figure};
use sph::output::plot::{write_png, write_rgb_png};
use sph::render::colormap::ColorRange;
use sph::render::frames::FrameParticles;
use sph::render::picture::{FrameStyle, render_frame};
use sph::render::projection::{Projection, View};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn sph(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .output()
        .expect("the sph binary runs")
}

fn sph_ok(args: &[&str]) -> String {
    let out = sph(args);
    assert!(
        out.status.success(),
        "sph {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The 2D dam break at a = 10 dx (about 100 fluid particles) to t = 0.06 s, frames every
/// 0.02 s: four frames, a probe with reference data, corrected steps.
fn tiny_2d_run(dir: &Path) -> PathBuf {
    let run = dir.join("run2d");
    let scene = format!("{ROOT}/scenes/dam_break_2d.toml");
    sph_ok(&[
        "run",
        &scene,
        "--out",
        run.to_str().unwrap(),
        "--end-time",
        "0.06",
        "--set",
        "particles.spacing=0.025",
        "--set",
        "output.interval=0.02",
        "--threads",
        "1",
    ]);
    run
}

/// The 3D column scene at 5 cm spacing to t = 0.02 s.
fn tiny_3d_run(dir: &Path) -> PathBuf {
    let run = dir.join("run3d");
    let scene = format!("{ROOT}/scenes/dam_break_column_3d.toml");
    sph_ok(&[
        "run",
        &scene,
        "--out",
        run.to_str().unwrap(),
        "--end-time",
        "0.02",
        "--set",
        "particles.spacing=0.05",
        // Room for the tank's two wall layers at this spacing.
        "--set",
        "domain.min=[-0.15,-0.15,-0.15]",
        "--set",
        "domain.max=[1.8,0.8,0.9]",
        "--set",
        "output.interval=0.01",
        "--threads",
        "1",
    ]);
    run
}

/// An RGB image read back from a PNG.
struct Image {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Image {
    fn read(path: &Path) -> Image {
        let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut reader = png::Decoder::new(std::io::BufReader::new(file))
            .read_info()
            .unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.bit_depth, png::BitDepth::Eight, "{}", path.display());
        let rgb = match info.color_type {
            png::ColorType::Rgb => buf[..info.buffer_size()].to_vec(),
            png::ColorType::Rgba => buf[..info.buffer_size()]
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect(),
            other => panic!("{}: unexpected colour type {other:?}", path.display()),
        };
        Image {
            width: info.width,
            height: info.height,
            rgb,
        }
    }

    fn pixels(&self) -> impl Iterator<Item = [u8; 3]> + '_ {
        self.rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]])
    }

    fn distinct_colors(&self) -> usize {
        let mut set: Vec<[u8; 3]> = self.pixels().collect();
        set.sort_unstable();
        set.dedup();
        set.len()
    }

    /// Pixels with a clear hue (not white, black or grey): the fluid's colour-mapped discs and
    /// the colour bar.
    fn colored_pixels(&self) -> usize {
        self.pixels()
            .filter(|p| p.iter().max().unwrap() - p.iter().min().unwrap() > 40)
            .count()
    }

    /// Grey pixels between black and white: solid particles.
    fn grey_pixels(&self) -> usize {
        self.pixels()
            .filter(|p| p[0] == p[1] && p[1] == p[2] && (90..=210).contains(&p[0]))
            .count()
    }

    /// The bytes of columns `x0..width`.
    fn right_part(&self, x0: u32) -> Vec<u8> {
        (0..self.height)
            .flat_map(|y| {
                let row = 3 * (y * self.width) as usize;
                self.rgb[row + 3 * x0 as usize..row + 3 * self.width as usize].to_vec()
            })
            .collect()
    }
}

fn png_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "png"))
        .collect();
    files.sort();
    files
}

#[test]
fn render_draws_every_frame_of_a_2d_run_on_one_colour_scale() {
    let dir = scratch("render2d");
    let run = tiny_2d_run(&dir);
    let out = dir.join("pictures");
    let stdout = sph_ok(&["render", run.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(stdout.contains("wrote 4 pictures"), "{stdout}");
    let files = png_files(&out);
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into())
        .collect();
    assert_eq!(
        names,
        [
            "frame_00000.png",
            "frame_00001.png",
            "frame_00002.png",
            "frame_00003.png"
        ]
    );
    let images: Vec<Image> = files.iter().map(|f| Image::read(f)).collect();
    for (image, file) in images.iter().zip(&files) {
        assert_eq!(image.width, 1200, "{}", file.display());
        assert!(image.height >= 200 && image.height <= 1920, "{}", image.height);
        assert!(image.distinct_colors() > 20, "{} is nearly blank", file.display());
        // The colour bar alone is about 1.2 t x 12 t = 22 x 230 px; the fluid adds its discs.
        assert!(
            image.colored_pixels() > 8000,
            "{}: {}",
            file.display(),
            image.colored_pixels()
        );
        assert!(
            image.grey_pixels() > 1000,
            "{}: tank walls missing",
            file.display()
        );
    }
    // One colour range for the whole run: the colour bar panel (right of the picture) is the
    // same in the first and the last frame, while the pictures differ (the column collapses).
    let panel = 1200 - (9.5f64 * 1200.0 / 64.0).round() as u32;
    let (first, last) = (&images[0], &images[3]);
    assert_eq!(first.right_part(panel), last.right_part(panel));
    assert_ne!(first.rgb, last.rgb);

    // --every 2 draws frames 0 and 2; other options reach the pictures.
    let every = dir.join("every");
    sph_ok(&[
        "render",
        run.to_str().unwrap(),
        "--every",
        "2",
        "--color",
        "pressure",
        "--width",
        "400",
        "--out",
        every.to_str().unwrap(),
    ]);
    let files = png_files(&every);
    assert_eq!(files.len(), 2);
    assert!(files[1].ends_with("frame_00002.png"));
    assert_eq!(Image::read(&files[0]).width, 400);
    // A 2D run has only its x-y plane.
    fails_with(
        &["render", run.to_str().unwrap(), "--view", "iso"],
        "needs a 3D run",
    );
}

#[test]
fn render_draws_a_3d_run_in_each_view() {
    let dir = scratch("render3d");
    let run = tiny_3d_run(&dir);
    let mut pictures = Vec::new();
    for view in ["side", "top", "iso"] {
        let out = dir.join(view);
        sph_ok(&[
            "render",
            run.to_str().unwrap(),
            "--view",
            view,
            "--width",
            "600",
            "--out",
            out.to_str().unwrap(),
        ]);
        let files = png_files(&out);
        assert_eq!(files.len(), 3, "{view}");
        let image = Image::read(files.last().unwrap());
        assert_eq!(image.width, 600, "{view}");
        assert!(image.distinct_colors() > 20, "{view} is nearly blank");
        assert!(
            image.colored_pixels() > 3000,
            "{view}: {}",
            image.colored_pixels()
        );
        assert!(image.grey_pixels() > 1000, "{view}: solids missing");
        pictures.push(image);
    }
    // Different views give different pictures (side and top even differ in height).
    assert_ne!(pictures[0].rgb, pictures[2].rgb);
    assert_ne!(pictures[1].rgb, pictures[2].rgb);
}

#[test]
fn plot_charts_forces_probes_and_steps_with_reference_data() {
    let dir = scratch("plot");
    let run = tiny_2d_run(&dir);
    let out = dir.join("charts");
    let scene = format!("{ROOT}/scenes/dam_break_2d.toml");
    // A made-up front record in the format of the scene's reference file (the chart is tested,
    // not the data).
    let refs = dir.join("reference");
    std::fs::create_dir_all(&refs).unwrap();
    std::fs::write(
        refs.join("martin_moyce_1952_surge_front.csv"),
        "series,n2_height_over_width,a_column_width_in,T_n_t_sqrt_g_over_a,Z_front_over_a\n\
         MM1952_n2-1_jaxsph,1,,0.1,1.01\nMM1952_n2-1_jaxsph,1,,0.3,1.05\n\
         MM1952_n2-1_trixiparticles,1,,0.2,1.02\nMM1952_n2-1_trixiparticles,1,,0.4,1.08\n",
    )
    .unwrap();
    let refs = refs.to_str().unwrap();
    sph_ok(&[
        "plot",
        run.to_str().unwrap(),
        "--scene",
        &scene,
        "--reference-dir",
        refs,
        "--out",
        out.to_str().unwrap(),
    ]);
    let names: Vec<String> = png_files(&out)
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into())
        .collect();
    assert_eq!(
        names,
        [
            "compression_and_deficit.png",
            "correction_iterations.png",
            "force_tank.png",
            "front_reference.png",
            "probe_front.png",
            "time_step.png"
        ]
    );
    for name in &names {
        let image = Image::read(&out.join(name));
        assert_eq!((image.width, image.height), (900, 600), "{name}");
        assert!(image.distinct_colors() > 10, "{name} is nearly blank");
        // A drawn curve: Tableau blue (31, 119, 180) and its antialiased edges.
        assert!(image.colored_pixels() > 200, "{name}: {}", image.colored_pixels());
    }
    // Without --scene: the scene file named in summary.json gives the reference chart, by
    // default into RUN_DIR/plots.
    sph_ok(&["plot", run.to_str().unwrap(), "--reference-dir", refs]);
    let own = png_files(&run.join("plots"));
    assert_eq!(own.len(), 6);
    assert!(own.iter().any(|f| f.ends_with("front_reference.png")));
    // A run whose summary names no scene file (or one that is gone): no reference chart.
    let summary_path = run.join("summary.json");
    let mut summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&summary_path).unwrap()).unwrap();
    assert!(
        summary["scene_file"]
            .as_str()
            .unwrap()
            .ends_with("dam_break_2d.toml")
    );
    summary["scene_file"] = "/no/such/scene.toml".into();
    std::fs::write(&summary_path, serde_json::to_vec(&summary).unwrap()).unwrap();
    let plain_dir = dir.join("plain");
    sph_ok(&[
        "plot",
        run.to_str().unwrap(),
        "--out",
        plain_dir.to_str().unwrap(),
    ]);
    let plain = png_files(&plain_dir);
    assert_eq!(plain.len(), 5);
    assert!(!plain.iter().any(|f| f.ends_with("front_reference.png")));
}

/// Runs `sph args` expecting failure with one line on stderr containing `needle`.
fn fails_with(args: &[&str], needle: &str) {
    let out = sph(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "sph {args:?} succeeded");
    assert_eq!(stderr.trim_end().lines().count(), 1, "sph {args:?}: {stderr}");
    assert!(stderr.contains(needle), "sph {args:?}: {stderr}");
}

#[test]
fn bad_run_directories_fail_with_one_line() {
    let dir = scratch("errors");
    let missing = dir.join("no_such_run");
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let (missing, empty) = (missing.to_str().unwrap(), empty.to_str().unwrap());
    fails_with(&["render", missing], "does not exist");
    fails_with(&["render", empty], "has no frames");
    fails_with(&["plot", missing], "does not exist");
    fails_with(&["plot", empty], "has no forces.csv, probes.csv or steps.csv");
    fails_with(&["render", empty, "--every", "0"], "--every must be at least 1");
    // An empty series and a frame that is not a VTK file.
    let run = dir.join("broken");
    std::fs::create_dir_all(run.join("frames")).unwrap();
    let pvd = run.join("particles.pvd");
    std::fs::write(
        &pvd,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\"><Collection>\n</Collection></VTKFile>\n",
    )
    .unwrap();
    fails_with(&["render", run.to_str().unwrap()], "has no frames");
    std::fs::write(
        &pvd,
        "<VTKFile type=\"Collection\"><Collection><DataSet timestep=\"0\" file=\"frames/f.vtu\"/></Collection></VTKFile>",
    )
    .unwrap();
    std::fs::write(run.join("frames/f.vtu"), "not a frame").unwrap();
    fails_with(&["render", run.to_str().unwrap()], "f.vtu");
    assert!(!run.join("render_side_speed").join("frame_00000.png").exists());
    // A malformed log names its file and line.
    std::fs::write(run.join("steps.csv"), "step,t_s\n1,0.1,7\n").unwrap();
    fails_with(
        &["plot", run.to_str().unwrap()],
        "steps.csv:2: 3 fields, the header has 2",
    );
}

/// A fluid block of `nx` x `ny` x `nz` particles at spacing `dx` from the origin, coloured by
/// the x index (0 .. nx-1), plus solid particles `solids` of the given kinds.
fn block(nx: usize, ny: usize, nz: usize, dx: f32, solids: &[([f32; 3], u32)]) -> FrameParticles {
    let mut p = FrameParticles::default();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                p.position
                    .push([dx * (i as f32 + 0.5), dx * (j as f32 + 0.5), dx * k as f32]);
                p.value.push(i as f64);
                p.kind.push(0);
            }
        }
    }
    for &(x, kind) in solids {
        p.position.push(x);
        p.value.push(f64::NAN);
        p.kind.push(kind);
    }
    p
}

/// The picture-plane bounds of `p` under `projection`, padded by one spacing `dx`.
fn bounds(p: &FrameParticles, projection: &Projection, dx: f64) -> (f64, f64, f64, f64) {
    p.position.iter().fold(
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY),
        |b, x| {
            let q = projection.project(*x);
            (
                b.0.min(q.u - dx),
                b.1.max(q.u + dx),
                b.2.min(q.v - dx),
                b.3.max(q.v + dx),
            )
        },
    )
}

/// Compares `canvas` with `tests/golden/<name>` (or writes it with `SPH_BLESS=1`): same size,
/// and at most 0.5 % of the pixels differ by more than 8 in a channel (room for a font
/// rasteriser update, not for a moved disc or another colour map).
fn check_golden(name: &str, canvas: &sph::render::raster::Canvas) {
    let path = Path::new(ROOT).join("tests/golden").join(name);
    if std::env::var_os("SPH_BLESS").is_some_and(|v| v == "1") {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        write_rgb_png(&canvas.pixels, (canvas.width, canvas.height), &path).unwrap();
        return;
    }
    assert!(
        path.is_file(),
        "golden {} is missing: run with SPH_BLESS=1 once, check the picture, commit it",
        path.display()
    );
    let golden = Image::read(&path);
    assert_eq!(
        (golden.width, golden.height),
        (canvas.width, canvas.height),
        "{name}: size"
    );
    let differing = golden
        .rgb
        .chunks_exact(3)
        .zip(canvas.pixels.chunks_exact(3))
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    let allowed = (golden.rgb.len() / 3) / 200;
    assert!(
        differing <= allowed,
        "{name}: {differing} pixels differ from the golden (allowed {allowed})"
    );
}

#[test]
fn golden_2d_frame_matches_the_stored_picture() {
    let dx = 0.01f32;
    // A floor (first solid) under the block and a post (second solid) to its right.
    let mut solids: Vec<([f32; 3], u32)> = (0..20)
        .map(|i| ([dx * (i as f32 + 0.5), -0.5 * dx, 0.0], 1))
        .collect();
    solids.extend((0..8).map(|j| ([0.18, dx * (j as f32 + 0.5), 0.0], 2)));
    let particles = block(12, 8, 1, dx, &solids);
    let projection = Projection::plane();
    let style = FrameStyle {
        projection,
        shaded: false,
        bounds: bounds(&particles, &projection, f64::from(dx)),
        radius: 0.5 * f64::from(dx),
        range: ColorRange::new(0.0, 11.0),
        label: "speed [m/s]".into(),
        cutaway: None,
        width: 320,
    };
    let canvas = render_frame(&particles, 0.125, &style).unwrap();
    assert_eq!(style.size().unwrap(), (canvas.width, canvas.height));
    // The lowest and highest values take the colour map's ends, the floor its grey.
    let has = |c: [u8; 3]| canvas.pixels.chunks_exact(3).any(|p| p == c);
    assert!(has([68, 1, 84]) && has([253, 231, 37]) && has(sph::render::colormap::solid_grey(1)));
    check_golden("frame_2d.png", &canvas);
}

#[test]
fn golden_3d_iso_frame_matches_the_stored_picture() {
    let dx = 0.01f32;
    // A floor under the cube and a front wall (y < 0) that the iso view cuts away.
    let mut solids: Vec<([f32; 3], u32)> = Vec::new();
    for i in 0..10 {
        for j in 0..6 {
            solids.push(([dx * (i as f32 + 0.5), dx * (j as f32 + 0.5), -dx], 1));
        }
        for k in 0..6 {
            solids.push(([dx * (i as f32 + 0.5), -0.5 * dx, dx * k as f32], 1));
        }
    }
    let particles = block(6, 6, 6, dx, &solids);
    let projection = Projection::of_view(View::Iso);
    let fluid = (
        [0.005, 0.005, 0.0],
        [f64::from(5.5 * dx), f64::from(5.5 * dx), f64::from(5.0 * dx)],
    );
    let style = FrameStyle {
        projection,
        shaded: true,
        bounds: bounds(&particles, &projection, f64::from(dx)),
        radius: 0.5 * f64::from(dx),
        range: ColorRange::new(0.0, 5.0),
        label: "speed [m/s]".into(),
        cutaway: Some(fluid),
        width: 320,
    };
    let canvas = render_frame(&particles, 2.5, &style).unwrap();
    // Without the cut-away the front wall hides the cube's front face; with it the nearest
    // faces show the colour map's low end (x index 0 faces the camera on the -x side).
    let uncut = render_frame(
        &particles,
        2.5,
        &FrameStyle {
            cutaway: None,
            ..style.clone()
        },
    )
    .unwrap();
    assert_ne!(canvas.pixels, uncut.pixels);
    check_golden("frame_3d_iso.png", &canvas);
}

#[test]
fn bench_chart_is_log_log_with_one_line_per_backend() {
    let row = |particles: u64, backend: &str, device: &str, seconds: f64| BenchRow {
        particles,
        backend: backend.into(),
        device: device.into(),
        spacing: 0.01,
        seconds_per_step: seconds,
        seconds_per_sweep: seconds / 2.0,
        sweeps_per_step: 2.0,
        particle_steps_per_second: particles as f64 / seconds,
        interactions_per_second: 0.0,
        bytes_per_particle: 100.0,
        peak_resident_per_particle: 150.0,
        neighbours: 30.0,
        speedup: None,
        stages: Vec::new(),
        stage_sweeps: (0.0, 0.0),
    };
    let rows = [
        row(100_000, "cpu", "2 threads", 0.5),
        row(100_000, "cuda", "H100", 0.01),
        row(10_000, "cpu", "2 threads", 0.05),
        row(10_000, "cuda", "H100", 0.004),
    ];
    let figure = timing_figure(&rows);
    assert!(figure.log_x && figure.log_y);
    assert_eq!(figure.series.len(), 2);
    assert_eq!(figure.series[0].label, "cpu (2 threads)");
    assert_eq!(figure.series[0].points, vec![(1e4, 0.05), (1e5, 0.5)]);
    assert_eq!(figure.series[1].points, vec![(1e4, 0.004), (1e5, 0.01)]);
    let dir = scratch("bench");
    let path = dir.join("bench.png");
    write_png(&figure, &path, (900, 600)).unwrap();
    let image = Image::read(&path);
    assert_eq!((image.width, image.height), (900, 600));
    assert!(image.colored_pixels() > 200);
}

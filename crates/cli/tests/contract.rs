//! The CLI's contract: outputs, and every error path (exit 2, one message naming the file and
//! line, nothing on stdout).

#![allow(clippy::unwrap_used)] // Test code: a failed unwrap is a failed test.

use std::path::PathBuf;
use std::process::{Command, Output};

fn cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_accelviz-cli"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A scratch file with this content, unique to the test.
fn file(name: &str, content: &str) -> String {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("contract");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, content).unwrap();
    path.to_string_lossy().into_owned()
}

const SQUARE: &str =
    "# two triangles in the plane z = 0\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";

#[test]
fn query_prints_one_line_per_ray_in_order() {
    let mesh = file("square.obj", SQUARE);
    let rays = file(
        "rays.txt",
        "# comment\n0.75 0.25 1 0 0 -1\n0.25 0.75 2 0 0 -1\n5 5 1 0 0 -1\n0.25 0.75 2 0 0 -1 0 1.5\n",
    );
    for accel in [
        "brute",
        "bvh:middle",
        "bvh:median",
        "bvh:sah-binned",
        "bvh:sah-binned:4",
        "bvh:sah-sweep",
        "bvh4:middle",
        "bvh4:sah-binned:8",
        "bvh8:median",
        "bvh8:sah-sweep",
        "kd:middle",
        "kd:median",
        "kd:sah",
        "kd:sah-per-node",
        "kd:sah-perfect",
    ] {
        for extra in [
            &[][..],
            &["--order", "file-order"],
            &["--precision", "f64", "--robust"],
            &["--threads", "2"],
        ] {
            let mut args = vec!["query", "--mesh", &mesh, "--accel", accel, "--rays", &rays];
            args.extend_from_slice(extra);
            let output = cli(&args);
            assert!(output.status.success(), "{accel}: {}", stderr(&output));
            let lines: Vec<_> = stdout(&output).lines().map(str::to_owned).collect();
            assert_eq!(lines.len(), 4, "{accel}");
            let hit = |line: &str, triangle: &str, t: f64| {
                let words: Vec<_> = line.split(' ').collect();
                assert_eq!(&words[..2], ["HIT", triangle], "{accel}: {line}");
                let mantissa = words[2].split('e').next().unwrap();
                assert!(
                    mantissa.len() >= 10,
                    "{accel}: at least 9 significant digits: {line}"
                );
                assert_eq!(words[2].parse::<f64>().unwrap(), t, "{accel}: {line}");
            };
            hit(&lines[0], "0", 1.0);
            hit(&lines[1], "1", 2.0);
            assert_eq!(lines[2], "MISS");
            assert_eq!(
                lines[3], "MISS",
                "{accel}: t_max 1.5 is before the hit at 2"
            );
        }
    }
}

#[test]
fn slab_text_and_json() {
    let output = cli(&["slab", "--box", "0 0 0 1 1 1", "--ray", "-1 0.5 0 1 0 0"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        stdout(&output),
        "x: t_near = 1, t_far = 2\ny: t_near = -inf, t_far = inf\nz: t_near = -inf, t_far = inf\n\
         t_enter = 1 (max of the nears)\nt_exit = 2 (min of the fars)\nHIT\n"
    );
    let output = cli(&["slab", "--box", "0 0 1 1", "--ray", "2 0.5 1 0", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert_eq!(
        text.trim(),
        r#"{"axes":[{"t_near":-2,"t_far":-1},{"t_near":-1e999,"t_far":1e999}],"t_enter":-2,"t_exit":-1,"hit":false}"#
    );
    let value: serde_json::Value = serde_json::from_str(text.trim()).unwrap_or_else(|_| {
        // serde_json refuses 1e999; check the rest by replacing the infinities.
        serde_json::from_str(&text.replace("1e999", "1e308")).unwrap()
    });
    assert_eq!(value["hit"], false);
}

#[test]
fn bench_reports_one_json_object_per_spec() {
    let output = cli(&[
        "bench",
        "--accel",
        "brute,bvh:sah-binned:8,bvh:sah-sweep",
        "--mesh",
        "builtin:icosphere",
        "--rays",
        "500",
        "--json",
        "--threads",
        "2",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let lines: Vec<serde_json::Value> = stdout(&output)
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    assert_eq!(lines.len(), 3);
    for key in [
        "accel",
        "triangles",
        "build_ms",
        "nodes",
        "leaves",
        "max_depth",
        "sah_cost",
        "rays",
        "trace_ms",
        "mrays_per_s",
        "avg_nodes_visited",
        "avg_prims_tested",
        "hits",
    ] {
        assert!(
            lines.iter().all(|line| !line[key].is_null()),
            "missing {key}"
        );
    }
    assert_eq!(lines[1]["accel"], "bvh:sah-binned:8");
    assert_eq!(lines[0]["triangles"], 5120);
    // Every structure finds the same hits as brute force.
    assert_eq!(lines[0]["hits"], lines[1]["hits"]);
    assert_eq!(lines[0]["hits"], lines[2]["hits"]);
    assert_eq!(lines[0]["avg_prims_tested"], 5120.0);
}

/// `bench --ray-kind`: shadow and ambient occlusion rays ask for any hit unless told, in file
/// order unless told, and the JSON echoes the kind, the query and the order, with the tree's
/// quality beside its speed: EPO (BVHs), bytes, the fill rate (wide trees) and the leaves'
/// sizes. Any-hit never visits more nodes than closest-hit on the same rays in the same
/// order, and finds them blocked as often.
#[test]
fn bench_ray_kinds_queries_and_quality() {
    let run = |extra: &[&str]| -> Vec<serde_json::Value> {
        let mut args = vec![
            "bench",
            "--mesh",
            "builtin:teapot",
            "--accel",
            "bvh:sah-binned,bvh8:sah-binned,kd:sah",
            "--repeat",
            "1",
            "--json",
        ];
        args.extend_from_slice(extra);
        let output = cli(&args);
        assert!(output.status.success(), "{}", stderr(&output));
        stdout(&output)
            .lines()
            .map(|line| serde_json::from_str(line).unwrap())
            .collect()
    };
    let any = run(&["--ray-kind", "ao", "--rays", "2000"]);
    let closest = run(&[
        "--ray-kind",
        "ao",
        "--rays",
        "2000",
        "--query",
        "closest",
        "--order",
        "file-order",
    ]);
    let closest_default = run(&["--ray-kind", "ao", "--rays", "10", "--query", "closest"]);
    assert_eq!(closest_default[0]["order"], "near-first");
    for (any, closest) in any.iter().zip(&closest) {
        assert_eq!(any["ray_kind"], "ao");
        assert_eq!(any["query"], "any");
        assert_eq!(any["order"], "file-order");
        assert_eq!(closest["query"], "closest");
        assert_eq!(any["hits"], closest["hits"], "{any}");
        assert!(
            any["avg_nodes_visited"].as_f64().unwrap()
                <= closest["avg_nodes_visited"].as_f64().unwrap(),
            "{any}"
        );
        assert!(any["bytes"].as_u64().unwrap() > 0);
        // The deepest stack: one waiting node a level at most, seven for an 8-wide node.
        let stack = any["max_stack"].as_u64().unwrap();
        let depth = any["max_depth"].as_u64().unwrap();
        let per_level = if any["accel"].as_str().unwrap().starts_with("bvh8") {
            7
        } else {
            1
        };
        assert!(stack >= 1 && stack <= per_level * depth, "{any}");
        let per = any["bytes_per_primitive"].as_f64().unwrap();
        assert!(
            (per - any["bytes"].as_f64().unwrap() / any["triangles"].as_f64().unwrap()).abs()
                < 1e-9
        );
        let leaves: u64 = any["leaf_sizes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|count| count.as_u64().unwrap())
            .sum();
        let accel = any["accel"].as_str().unwrap();
        // The SAH's chances against the rays' (binary trees): every ray entering the root is
        // one entry at depth 0, and the measured entries over all depths are the nodes
        // visited.
        let check = &any["sah_check"];
        if accel.starts_with("bvh8") {
            assert!(check.is_null());
        } else {
            let depths = check["per_depth"].as_array().unwrap();
            assert_eq!(depths[0][0], 0);
            assert_eq!(depths[0][1].as_f64(), Some(1.0));
            assert_eq!(depths[0][2].as_f64(), Some(1.0));
            let entered: f64 = depths.iter().map(|depth| depth[2].as_f64().unwrap()).sum();
            let rays_entering = check["rays_entering"].as_f64().unwrap();
            let visited =
                any["avg_nodes_visited"].as_f64().unwrap() * any["rays"].as_f64().unwrap();
            assert!(
                (entered * rays_entering - visited).abs() < 1e-6 * visited,
                "{check}"
            );
            assert!(check["measured_chance_cost"].as_f64().unwrap() > 0.0);
        }
        match accel {
            "kd:sah" => {
                assert!(any["epo"].is_null() && any["fill_rate"].is_null());
                assert_eq!(leaves, any["leaves"].as_u64().unwrap());
            }
            "bvh8:sah-binned:16" => {
                let fill = any["fill_rate"].as_f64().unwrap();
                assert!(fill > 0.0 && fill <= 1.0, "{any}");
                assert!(any["epo"].as_f64().unwrap() > 0.0);
            }
            _ => {
                assert!(any["fill_rate"].is_null(), "{any}");
                assert!(any["epo"].as_f64().unwrap() > 0.0);
                assert_eq!(leaves, any["leaves"].as_u64().unwrap());
            }
        }
    }
    let camera = run(&["--ray-kind", "camera", "--rays", "100"]);
    assert_eq!(camera[0]["rays"], 100, "a 10 x 10 camera");
    assert_eq!(camera[0]["query"], "closest");
}

#[test]
fn bench_aimed_rays_never_slip_through_in_robust_mode() {
    let output = cli(&[
        "bench",
        "--mesh",
        "builtin:icosphere",
        "--aimed",
        "--accel",
        "bvh:sah-binned",
        "--robust",
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let value: serde_json::Value = serde_json::from_str(stdout(&output).trim()).unwrap();
    assert_eq!(value["misses"], 0);
    assert_eq!(value["rays"], 5120 * 18);
    // Held to the reference: no leak, false hit or wrong answer; and the outcomes add up.
    let outcomes = &value["outcomes"];
    for name in ["leak", "false_hit", "wrong"] {
        assert_eq!(outcomes[name].as_f64(), Some(0.0), "{outcomes}");
    }
    let sum: f64 = ["agree", "tie", "graze"]
        .iter()
        .map(|name| outcomes[name].as_f64().unwrap())
        .sum();
    assert!((sum - 1e6).abs() < 1e-3, "{outcomes}");
    // The fast test leaks through the same sphere.
    let fast = cli(&[
        "bench",
        "--mesh",
        "builtin:icosphere",
        "--ray-kind",
        "aimed",
        "--accel",
        "bvh:sah-binned",
        "--json",
    ]);
    let fast: serde_json::Value = serde_json::from_str(stdout(&fast).trim()).unwrap();
    assert!(fast["outcomes"]["leak"].as_f64().unwrap() > 0.0, "{fast}");
}

#[test]
fn bench_camera_rays_and_their_errors() {
    let output = cli(&[
        "bench",
        "--accel",
        "bvh:median",
        "--camera",
        "16x8",
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let value: serde_json::Value = serde_json::from_str(stdout(&output).trim()).unwrap();
    assert_eq!(
        (value["rays"].as_u64(), value["ray_source"].as_str()),
        (Some(128), Some("camera:16x8"))
    );
    assert_fails(
        &["bench", "--accel", "bvh:median", "--camera", "0x8"],
        "--camera: '0x8' is not WIDTHxHEIGHT",
    );
    assert_fails(
        &["bench", "--accel", "bvh:median", "--threads", "0"],
        "--threads must be at least 1",
    );
    assert_fails(
        &["bench", "--accel", "bvh:median", "--traversal-cost=-1"],
        "must be positive numbers",
    );
}

/// Packets, thread counts and instruction sets are axes of one measurement: each combination
/// is a row, with the same hits.
#[test]
fn bench_measures_packets_threads_and_instruction_sets_alike() {
    for rays in [&["--camera", "24x16"][..], &["--rays", "300"]] {
        let mut args = vec![
            "bench",
            "--mesh",
            "builtin:icosphere",
            "--accel",
            "bvh8:sah-binned,bvh:median",
            "--packet",
            "1,16,64",
            "--threads",
            "1,2",
            "--isa",
            "portable",
            "--repeat",
            "2",
            "--json",
        ];
        args.extend_from_slice(rays);
        let output = cli(&args);
        assert!(output.status.success(), "{}", stderr(&output));
        let rows: Vec<serde_json::Value> = stdout(&output)
            .lines()
            .map(|line| serde_json::from_str(line).unwrap())
            .collect();
        assert_eq!(rows.len(), 2 * 3 * 2);
        for row in &rows {
            assert_eq!(row["hits"], rows[0]["hits"], "{row}");
            assert_eq!(row["isa"], "portable");
            assert!(row["trace_ms_min"].as_f64().unwrap() <= row["trace_ms"].as_f64().unwrap());
            assert!(row["trace_ms"].as_f64().unwrap() <= row["trace_ms_max"].as_f64().unwrap());
        }
        assert!(
            rows.iter()
                .any(|row| row["packet"] == 64 && row["threads"] == 2)
        );
    }
    assert_fails(
        &["bench", "--accel", "bvh8:median", "--packet", "65"],
        "--packet must be a whole number from 1 to 64",
    );
    assert_fails(
        &["bench", "--accel", "bvh8:median", "--isa", "neon"],
        "unknown instruction set 'neon'; valid ones are: portable, simd128, avx2, avx512",
    );
}

#[test]
fn bench_reads_a_ray_file() {
    let mesh = file("square-bench.obj", SQUARE);
    let rays = file("bench-rays.txt", "0.75 0.25 1 0 0 -1\n5 5 1 0 0 -1\n");
    let output = cli(&[
        "bench",
        "--mesh",
        &mesh,
        "--accel",
        "bvh:median",
        "--rays-file",
        &rays,
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let value: serde_json::Value = serde_json::from_str(stdout(&output).trim()).unwrap();
    assert_eq!(
        (value["rays"].as_u64(), value["hits"].as_u64()),
        (Some(2), Some(1))
    );
}

/// `bench --rays-file` holds each ray once, as the precision it traces in has it (32 bytes in
/// f32), and no ray's reference: half a million rays peak far below what the file's text and
/// its rays in f64 took (200 bytes a ray: 2 GB for ten million). Its peak resident memory is
/// read from /proc while it runs.
#[cfg(target_os = "linux")]
#[test]
fn bench_traces_a_large_ray_file_in_bounded_memory() {
    let mesh = file("square-large-file.obj", SQUARE);
    let count = 500_000u32;
    let mut text = String::with_capacity(count as usize * 40);
    for index in 0..count {
        let x = f64::from(index % 1000) / 999.0 * 1.2 - 0.1;
        let y = f64::from(index / 1000) / f64::from(count / 1000) * 1.2 - 0.1;
        text.push_str(&format!("{x:.6} {y:.6} 1 0.01 -0.02 -1\n"));
    }
    let rays = file("large-bench-rays.txt", &text);
    drop(text);
    let mut child = Command::new(env!("CARGO_BIN_EXE_accelviz-cli"))
        .args([
            "bench",
            "--mesh",
            &mesh,
            "--accel",
            "bvh:median,kd:sah",
            "--rays-file",
            &rays,
            "--repeat",
            "1",
            "--json",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let status = format!("/proc/{}/status", child.id());
    let mut peak_kb = 0u64;
    while child.try_wait().expect("it runs").is_none() {
        if let Some(peak) = std::fs::read_to_string(&status).ok().and_then(|text| {
            text.lines()
                .find_map(|line| line.strip_prefix("VmHWM:"))
                .and_then(|value| value.trim().trim_end_matches("kB").trim().parse().ok())
        }) {
            peak_kb = peak;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let output = child.wait_with_output().expect("it ends");
    assert!(output.status.success(), "{}", stderr(&output));
    let value: serde_json::Value =
        serde_json::from_str(stdout(&output).lines().next().unwrap()).unwrap();
    assert_eq!(value["rays"].as_u64(), Some(u64::from(count)));
    println!("peak {peak_kb} kB for {count} rays");
    // The program itself, then 64 bytes a ray at most.
    let bound_kb = 40_000 + u64::from(count) * 64 / 1024;
    assert!(
        peak_kb > 0 && peak_kb < bound_kb,
        "peak {peak_kb} kB for {count} rays, above {bound_kb} kB"
    );
}

/// Runs a failing command: exit 2, nothing on stdout, one line on stderr containing `expected`.
fn assert_fails(args: &[&str], expected: &str) {
    let output = cli(args);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "{args:?}: {message}");
    assert!(
        output.stdout.is_empty(),
        "{args:?}: partial output {:?}",
        stdout(&output)
    );
    assert!(
        message.contains(expected),
        "{args:?}: {message:?} should contain {expected:?}"
    );
    assert!(!message.contains("panicked"), "{args:?}: {message}");
}

/// A ray file of many blocks (the query reads about two megabytes at a time): every thread
/// count answers the same lines in the same order, and a bad line far into the file stops the
/// query before it writes anything.
#[test]
fn query_streams_large_files_on_any_number_of_threads() {
    let mesh = file("big-square.obj", SQUARE);
    let mut text = String::new();
    for index in 0..120_000u32 {
        let x = f64::from(index % 1000) / 999.0 * 1.2 - 0.1;
        let y = f64::from(index / 1000) / 119.0;
        text.push_str(&format!("{x:.6} {y:.6} 1 0 0 -1\n"));
    }
    let rays = file("many-rays.txt", &text);
    let answers: Vec<String> = ["1", "2"]
        .iter()
        .map(|threads| {
            let output = cli(&[
                "query",
                "--mesh",
                &mesh,
                "--accel",
                "bvh8:sah-binned",
                "--rays",
                &rays,
                "--threads",
                threads,
            ]);
            assert!(output.status.success(), "{}", stderr(&output));
            stdout(&output)
        })
        .collect();
    assert_eq!(answers[0], answers[1]);
    let lines: Vec<&str> = answers[0].lines().collect();
    assert_eq!(lines.len(), 120_000);
    assert!(lines[0].starts_with("MISS") && lines[500].starts_with("HIT"));
    text.push_str("0.5 0.5 1 0 0\n");
    let bad = file("many-rays-bad.txt", &text);
    let output = cli(&[
        "query",
        "--mesh",
        &mesh,
        "--accel",
        "bvh4:median",
        "--rays",
        &bad,
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stdout(&output).is_empty(), "no partial output");
    assert!(
        stderr(&output).contains(
            "many-rays-bad.txt:120001: a ray is 'ox oy oz dx dy dz [tmin tmax]', found 5 values"
        ),
        "{}",
        stderr(&output)
    );
}

#[test]
fn bad_input_fails_cleanly() {
    let mesh = file("good.obj", SQUARE);
    let rays = file("good-rays.txt", "0.5 0.5 1 0 0 -1\n");
    let query = |mesh: &str, accel: &str, rays: &str| -> Vec<String> {
        ["query", "--mesh", mesh, "--accel", accel, "--rays", rays]
            .map(str::to_owned)
            .to_vec()
    };
    let run = |args: Vec<String>, expected: &str| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        assert_fails(&args, expected);
    };
    // Files.
    run(
        query("/no/such/mesh.obj", "brute", &rays),
        "/no/such/mesh.obj: cannot read the file",
    );
    run(
        query(&mesh, "brute", "/no/such/rays.txt"),
        "/no/such/rays.txt: cannot read the file",
    );
    let malformed = file("malformed.obj", "v 0 0 0\nv 1 0 0\nv 0 one 0\nf 1 2 3\n");
    run(
        query(&malformed, "brute", &rays),
        "malformed.obj:3: 'one' is not a number",
    );
    let out_of_range = file("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    run(
        query(&out_of_range, "brute", &rays),
        "range.obj:5: vertex index 9 is out of range",
    );
    let nan_mesh = file("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 NaN 0\nf 1 2 3\n");
    run(
        query(&nan_mesh, "brute", &rays),
        "nan.obj:3: vertex coordinate is not finite",
    );
    let inf_mesh = file("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n");
    run(
        query(&inf_mesh, "brute", &rays),
        "inf.obj:3: vertex coordinate is not finite",
    );
    let binary = std::path::Path::new(&file("binary.obj", "")).to_owned();
    std::fs::write(&binary, [0x76, 0x20, 0xff, 0xfe, 0x0a]).unwrap();
    run(
        query(binary.to_str().unwrap(), "brute", &rays),
        "binary.obj:1: the file is not UTF-8 text",
    );
    // Rays.
    let zero = file("zero.txt", "0.5 0.5 1 0 0 -1\n0 0 0 0 0 0\n");
    run(
        query(&mesh, "brute", &zero),
        "zero.txt:2: bad ray: the direction is zero",
    );
    let nan_ray = file("nan-ray.txt", "# c\n0.5 nan 1 0 0 -1\n");
    run(
        query(&mesh, "brute", &nan_ray),
        "nan-ray.txt:2: bad ray: the origin is not finite",
    );
    let short = file("short.txt", "0.5 0.5 1 0 0 -1\n1 2 3\n");
    run(
        query(&mesh, "brute", &short),
        "short.txt:2: a ray is 'ox oy oz dx dy dz [tmin tmax]', found 3 values",
    );
    let inf_ray = file("inf-ray.txt", "0.5 0.5 1 inf 0 -1\n");
    run(
        query(&mesh, "brute", &inf_ray),
        "inf-ray.txt:1: bad ray: the direction is not finite",
    );
    // Specs.
    run(
        query(&mesh, "bvh:octree", &rays),
        "unknown accelerator 'bvh:octree'; valid ones are: brute, bvh:middle",
    );
    run(
        query(&mesh, "bvh:sah-binned:1", &rays),
        "the bins must be a whole number from 2 to 4096",
    );
    run(
        query(&mesh, "bvh16:middle", &rays),
        "unknown accelerator 'bvh16:middle'",
    );
    run(
        query(&mesh, "bvh8:sah-binned:1", &rays),
        "'bvh8:sah-binned:1': the bins must be a whole number from 2 to 4096",
    );
    let long = file(
        "long-line.txt",
        &format!("0.5 0.5 1 0 0 -1\n{}\n", "1 ".repeat(3000)),
    );
    run(
        query(&mesh, "brute", &long),
        "long-line.txt:2: the line is longer than 4096 bytes",
    );
    let mut args = query(&mesh, "brute", &rays);
    args.extend(["--threads".to_owned(), "0".to_owned()]);
    run(args, "--threads must be at least 1");
    assert_fails(
        &["bench", "--accel", "bvh:median,kd:octree", "--rays", "10"],
        "unknown accelerator 'kd:octree'",
    );
    assert_fails(
        &["bench", "--accel", "bvh:median", "--mesh", "builtin:kettle"],
        "unknown built-in mesh 'kettle'",
    );
    // Slab.
    assert_fails(
        &["slab", "--box", "0 0 0 1 1 1", "--ray", "0 0 0 0 0 0"],
        "--ray: the direction is zero",
    );
    assert_fails(
        &["slab", "--box", "0 0 0 1 1", "--ray", "0 0 0 1 0 0"],
        "give 6 and 6 (3D) or 4 and 4 (2D)",
    );
    assert_fails(
        &["slab", "--box", "0 0 0 1 nan 1", "--ray", "0 0 0 1 0 0"],
        "--box: 'nan' is not a finite number",
    );
    // Usage errors exit 2 too (clap's convention).
    assert_fails(&["query", "--mesh", &mesh], "--accel");
}

#[test]
fn degenerate_triangles_keep_their_number_and_are_never_hit() {
    // Triangle 0 is degenerate (a repeated corner) and lies where the ray passes.
    let mesh = file(
        "degenerate.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 1 3\nf 1 2 3\n",
    );
    let rays = file("diagonal.txt", "0.5 0.5 1 0 0 -1\n0.75 0.25 1 0 0 -1\n");
    for precision in ["f32", "f64"] {
        for robust in [false, true] {
            let mut args = vec![
                "query",
                "--mesh",
                &mesh,
                "--accel",
                "bvh:sah-sweep",
                "--rays",
                &rays,
                "--precision",
                precision,
            ];
            if robust {
                args.push("--robust");
            }
            let output = cli(&args);
            let text = stdout(&output);
            let lines: Vec<_> = text.lines().collect();
            assert!(lines[0].starts_with("HIT 1 "), "{lines:?}");
            assert!(lines[1].starts_with("HIT 1 "), "{lines:?}");
        }
    }
}

/// The `sah` contract: the JSON shape of the issue, written-down costs for a tiny 2D scene,
/// the minima over what is listed, CSV rows, and its errors.
#[test]
fn sah_lists_every_candidate_with_its_parts() {
    // Two unit boxes 3 apart: kD cell 4 × 1 (perimeter 10). Cutting at x = 1 or x = 3 leaves
    // one box each side in cells of perimeter 4 and 8: 3 + 0.4 + 0.8 = 4.2.
    let scene = file("two-boxes.scene2d", "box 0 0 1 1\nbox 3 0 4 1\n");
    let output = cli(&[
        "sah",
        "--scene2d",
        &scene,
        "--structure",
        "kd",
        "--json",
        "--bins",
        "4",
        "--precision",
        "f64",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let json: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    let x = json["axes"]["x"].as_array().unwrap();
    let positions: Vec<f64> = x.iter().map(|c| c["position"].as_f64().unwrap()).collect();
    assert_eq!(positions, [1.0, 3.0]);
    for candidate in x {
        assert_eq!(candidate["cost"].as_f64().unwrap(), 4.2);
        assert_eq!(candidate["n_left"], 1);
        assert_eq!(candidate["n_right"], 1);
        for key in ["p_left", "p_right"] {
            assert!(candidate[key].as_f64().unwrap() > 0.0);
        }
    }
    assert_eq!(json["axes"]["y"].as_array().unwrap().len(), 0);
    assert!(json["axes"].get("z").is_none(), "a 2D scene has no z axis");
    assert_eq!(json["leaf_cost"].as_f64().unwrap(), 2.0);
    assert_eq!(json["best"]["axis"], "x");
    assert_eq!(json["best"]["position"].as_f64().unwrap(), 1.0);
    assert_eq!(json["middle"]["position"].as_f64().unwrap(), 2.0);
    assert!(json["median"]["cost"].as_f64().is_some());
    let binned = &json["binned"];
    assert_eq!(binned["axes"]["x"].as_array().unwrap().len(), 3);
    assert!(binned["best"]["cost"].as_f64().unwrap() >= json["best"]["cost"].as_f64().unwrap());

    // A mesh, one axis, CSV: one row per candidate, exact then binned.
    let mesh = file("sah-square.obj", SQUARE);
    let csv = cli(&[
        "sah",
        "--mesh",
        &mesh,
        "--structure",
        "bvh",
        "--axis",
        "y",
        "--csv",
        "--bins",
        "2",
    ]);
    assert!(csv.status.success(), "{}", stderr(&csv));
    let text = stdout(&csv);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("axis,kind,position,cost,n_left,n_right,p_left,p_right,area_left,area_right")
    );
    let rows: Vec<&str> = lines.collect();
    assert!(!rows.is_empty());
    assert!(
        rows.iter()
            .all(|row| row.starts_with("y,exact,") || row.starts_with("y,binned,"))
    );

    // Text, on a built-in mesh and a deeper node.
    let text = cli(&[
        "sah",
        "--mesh",
        "builtin:icosphere",
        "--structure",
        "kd",
        "--node",
        "LR",
    ]);
    assert!(text.status.success(), "{}", stderr(&text));
    assert!(stdout(&text).contains("SAH best"));

    // Errors.
    assert_fails(
        &["sah", "--mesh", &mesh, "--structure", "kd", "--node", "LQ"],
        "step 2 is 'Q'",
    );
    assert_fails(
        &[
            "sah",
            "--mesh",
            &mesh,
            "--structure",
            "bvh",
            "--node",
            "LLLLLLLL",
        ],
        "is a leaf",
    );
    assert_fails(
        &[
            "sah",
            "--scene2d",
            &scene,
            "--structure",
            "kd",
            "--axis",
            "z",
        ],
        "only x and y",
    );
    assert_fails(
        &["sah", "--mesh", &mesh, "--structure", "kd", "--bins", "1"],
        "--bins",
    );
    let bad_scene = file("bad.scene2d", "box 0 0 1 1\ncircle 1 2 3\n");
    assert_fails(
        &["sah", "--scene2d", &bad_scene, "--structure", "kd"],
        "bad.scene2d:2: unknown shape 'circle'",
    );
    assert_fails(
        &["sah", "--scene2d", "builtin:stadium", "--structure", "kd"],
        "unknown built-in 2D scene",
    );
}

/// `tradeoff`: every structure × switch row, in Markdown and CSV, and two plots; on rays aimed
/// at the vertices and edges of a closed mesh the watertight rows have no leaks, false hits
/// or wrong answers, and the fast rows leak somewhere.
#[test]
fn tradeoff_writes_the_table_and_the_plots() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("tradeoff");
    let _ = std::fs::remove_dir_all(&out);
    let out_text = out.to_string_lossy().into_owned();
    let examples = out.join("examples");
    let examples_text = examples.to_string_lossy().into_owned();
    let output = cli(&[
        "tradeoff",
        "--mesh",
        "builtin:icosphere",
        "--ray-kind",
        "aimed",
        "--rays",
        "600",
        "--repeat",
        "1",
        "--out",
        &out_text,
        "--examples",
        &examples_text,
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stdout(&output).contains("| kd:sah-perfect | near-first | f64 | watertight |"));
    let csv = std::fs::read_to_string(out.join("tradeoff.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[0], "structure");
    let rows: Vec<Vec<&str>> = lines.map(|line| line.split(',').collect()).collect();
    assert_eq!(
        rows.len(),
        accelviz_core::Structure::compared().len() * 5,
        "every structure of the catalogue, 5 switch settings each"
    );
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for row in &rows {
        for name in [
            "build_ms",
            "sah_cost",
            "nodes_per_ray",
            "prims_per_ray",
            "mrays_per_s",
        ] {
            let value: f64 = row[column(name)].parse().unwrap();
            assert!(value.is_finite() && value > 0.0, "{name} in {row:?}");
        }
        let outcomes: f64 = accelviz_core::outcome::Outcome::ALL
            .iter()
            .map(|outcome| {
                row[column(&format!("{}_per_million", outcome.name()))]
                    .parse::<f64>()
                    .unwrap()
            })
            .sum();
        assert!((outcomes - 1e6).abs() < 1e-3, "{row:?}");
        if row[column("triangle_test")] == "watertight" {
            for name in ["leak", "false_hit", "wrong"] {
                assert_eq!(row[column(&format!("{name}_per_million"))], "0", "{row:?}");
            }
        }
    }
    // The fast test leaks on these rays somewhere: the table shows the trade.
    assert!(rows.iter().any(
        |row| row[column("triangle_test")] == "fast" && row[column("leak_per_million")] != "0"
    ));
    // One ray of each outcome a row had, in a ray file that reads back; a fast f32 leak is
    // among them.
    let leak =
        std::fs::read_to_string(examples.join("bvh-sah-sweep_near-first_f32_fast.rays")).unwrap();
    assert!(leak.contains("# leak: "), "{leak}");
    let rays = accelviz_scene::rays::parse_rays(&leak, "examples").unwrap();
    assert!(rays.len() >= 2, "agree and leak at least: {leak}");
    let assumption = std::fs::read_to_string(out.join("sah-assumption.svg")).unwrap();
    assert!(assumption.contains(">kd:sah rays</text>"), "{assumption}");
    assert!(stdout(&output).contains("The SAH's assumption, checked"));
    let total = std::fs::read_to_string(out.join("total-vs-rays.svg")).unwrap();
    assert!(total.contains("<polyline") && total.contains(">bvh:middle</text>"));
    assert!(stdout(&output).contains("| rays | fastest | total ms |"));
    for plot in ["build-vs-traversal.svg", "predicted-vs-measured.svg"] {
        let svg = std::fs::read_to_string(out.join(plot)).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
            "{plot}"
        );
        // The legend names every family of the rows (grids and octrees were drawn and listed
        // as BVHs).
        for family in accelviz_core::Family::ALL {
            if accelviz_core::Structure::compared()
                .iter()
                .any(|structure| structure.family() == family)
            {
                assert!(
                    svg.contains(&format!(">{}</text>", family.label())),
                    "{plot}: {}",
                    family.label()
                );
            }
        }
        for structure in [
            "bvh:sah-binned:4",
            "bvh:sah-sweep",
            "kd:median",
            "kd:sah-perfect",
        ] {
            assert!(
                svg.contains(&format!(">{structure}</text>")),
                "{plot}: {structure}"
            );
        }
    }
    assert!(
        std::fs::read_to_string(out.join("tradeoff.md"))
            .unwrap()
            .contains("| structure |")
    );
    // Errors.
    let blocker = file("not-a-directory", "x");
    assert_fails(
        &[
            "tradeoff",
            "--mesh",
            "builtin:icosphere",
            "--rays",
            "10",
            "--out",
            &format!("{blocker}/sub"),
        ],
        "cannot create the directory",
    );
    assert_fails(&["tradeoff", "--rays", "0"], "--rays must be at least 1");
    assert_fails(&["tradeoff", "--mesh", "/no/such.obj"], "/no/such.obj");
}

/// `tradeoff --json`: one object per row with the ray kind, the query and every outcome per
/// million (adding up to a million); shadow rays default to the any-hit query.
#[test]
fn tradeoff_json_names_the_rays_the_query_and_the_outcomes() {
    let output = cli(&[
        "tradeoff",
        "--mesh",
        "builtin:teapot",
        "--ray-kind",
        "shadow",
        "--rays",
        "300",
        "--repeat",
        "1",
        "--json",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    let mut rows: Vec<serde_json::Value> = text
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    // The last object is the break-even, recomputed here from the rows' own figures: the
    // default switches' build time and speed.
    let break_even = rows.pop().unwrap();
    assert_eq!(rows.len(), accelviz_core::Structure::compared().len() * 5);
    let defaults: Vec<&serde_json::Value> = rows
        .iter()
        .filter(|row| {
            (
                row["order"].as_str(),
                row["precision"].as_str(),
                row["test"].as_str(),
            ) == (Some("near-first"), Some("f32"), Some("fast"))
        })
        .collect();
    let entries = break_even["break_even"].as_array().unwrap();
    assert_eq!(entries.len(), 7, "10^3 to 10^9 rays");
    let mut previous = 0.0;
    for entry in entries {
        let rays = entry["rays"].as_f64().unwrap();
        assert!(rays > previous, "rays ascending");
        previous = rays;
        let total = |row: &serde_json::Value| {
            row["build_ms"].as_f64().unwrap() + rays / (row["mrays_per_s"].as_f64().unwrap() * 1e3)
        };
        let best = defaults
            .iter()
            .min_by(|a, b| total(a).total_cmp(&total(b)))
            .unwrap();
        assert_eq!(entry["fastest"], best["structure"], "{entry}");
        let total_ms = entry["total_ms"].as_f64().unwrap();
        assert!((total_ms - total(best)).abs() <= 1e-9 * total_ms, "{entry}");
    }
    for crossing in break_even["crossovers"].as_array().unwrap() {
        assert!(crossing["rays"].as_f64().unwrap() >= 1e3, "{crossing}");
    }
    for row in &rows {
        assert_eq!(row["ray_kind"], "shadow", "{row}");
        assert_eq!(row["query"], "any", "{row}");
        assert!(["fast", "watertight"].contains(&row["test"].as_str().unwrap()));
        for field in [
            "build_ms",
            "sah_cost",
            "measured_cost",
            "mrays_per_s",
            "spread_pct",
        ] {
            assert!(row[field].as_f64().unwrap().is_finite(), "{field}: {row}");
        }
        // The end-point overlap: a BVH's; none for the structures that cut space (kD-trees,
        // grids, octrees), whose cells do not overlap.
        let structure = row["structure"].as_str().unwrap();
        if structure.starts_with("bvh") {
            assert!(row["epo"].as_f64().unwrap() > 0.0, "{row}");
        } else {
            assert!(row["epo"].is_null(), "{row}");
        }
        let sum: f64 = ["agree", "tie", "graze", "leak", "false_hit", "wrong"]
            .iter()
            .map(|name| row["outcomes"][name].as_f64().unwrap())
            .sum();
        assert!((sum - 1e6).abs() < 1e-3, "{row}");
    }
    assert_fails(
        &["tradeoff", "--ray-kind", "sideways"],
        "'sideways' is not a ray kind; ray kinds are random, camera, aimed, shadow, ao, bounce",
    );
    assert_fails(
        &["tradeoff", "--query", "nearest"],
        "'nearest' is not a query",
    );
}

/// `heatmap --ray-kind`: each pixel shows the cost of the secondary rays from its ray's hit,
/// the same every time; shadow and ao rays ask for any hit; kinds that are not a pixel's, and
/// packets of scattered rays, are refused.
#[test]
fn heatmap_of_secondary_rays() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("contract-heatmap-kinds");
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("map.png").to_string_lossy().into_owned();
    let run = |kind: &str| -> serde_json::Value {
        let output = cli(&[
            "heatmap",
            "--mesh",
            "builtin:teapot",
            "--accel",
            "bvh:sah-binned",
            "--camera",
            "64x64",
            "--ray-kind",
            kind,
            "--out",
            &png,
            "--json",
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        serde_json::from_str(stdout(&output).trim()).unwrap()
    };
    let camera = run("camera");
    assert_eq!(camera["query"], "closest");
    for kind in ["shadow", "ao", "bounce"] {
        let map = run(kind);
        assert_eq!(map["ray_kind"], kind);
        let expected = if kind == "bounce" { "closest" } else { "any" };
        assert_eq!(map["query"], expected);
        assert!(map["total"].as_u64().unwrap() > 0, "{map}");
        assert_eq!(
            map["total"],
            run(kind)["total"],
            "{kind}: the same every time"
        );
    }
    // Four short rays a hit cost more than the one camera ray.
    assert!(run("ao")["total"].as_u64() > camera["total"].as_u64());
    assert_fails(
        &[
            "heatmap",
            "--accel",
            "bvh:sah-binned",
            "--ray-kind",
            "aimed",
            "--out",
            &png,
        ],
        "a heat map shows the camera's pixels",
    );
    assert_fails(
        &[
            "heatmap",
            "--accel",
            "bvh:sah-binned",
            "--ray-kind",
            "ao",
            "--packet",
            "4",
            "--out",
            &png,
        ],
        "traced one at a time",
    );
}

#[test]
fn heatmap_totals_are_the_benchmarks_counts() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("contract-heatmap");
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("map.png").to_string_lossy().into_owned();
    let csv = dir.join("map.csv").to_string_lossy().into_owned();
    for (accel, order) in [("bvh:sah-binned", "near-first"), ("kd:sah", "file-order")] {
        let bench = cli(&[
            "bench", "--accel", accel, "--camera", "24x16", "--order", order, "--json",
        ]);
        assert!(bench.status.success(), "{}", stderr(&bench));
        let bench: serde_json::Value = serde_json::from_str(stdout(&bench).trim()).unwrap();
        let rays = bench["rays"].as_f64().unwrap();
        for (counter, average) in [
            ("nodes", "avg_nodes_visited"),
            ("boxes", "avg_box_tests"),
            ("prims", "avg_prims_tested"),
        ] {
            let output = cli(&[
                "heatmap",
                "--accel",
                accel,
                "--camera",
                "24x16",
                "--order",
                order,
                "--counter",
                counter,
                "--threads",
                "2",
                "--out",
                &png,
                "--csv",
                &csv,
                "--json",
            ]);
            assert!(output.status.success(), "{}", stderr(&output));
            let value: serde_json::Value = serde_json::from_str(stdout(&output).trim()).unwrap();
            let total = value["total"].as_u64().unwrap();
            let expected = bench[average].as_f64().unwrap() * rays;
            assert!(
                (total as f64 - expected).abs() < 1e-6 * expected.max(1.0),
                "{accel} {order} {counter}: heatmap {total}, bench {expected}"
            );
            for field in [
                "accel", "width", "height", "counter", "order", "max", "mean", "ms",
            ] {
                assert!(value.get(field).is_some(), "{field} missing");
            }
            assert_eq!(
                (value["width"].as_u64(), value["height"].as_u64()),
                (Some(24), Some(16))
            );
            assert_eq!(value["counter"].as_str(), Some(counter));
            assert_eq!(value["order"].as_str(), Some(order));
            // The CSV has every pixel, and its column sums to the total.
            let text = std::fs::read_to_string(&csv).unwrap();
            let mut lines = text.lines();
            assert_eq!(lines.next(), Some("x,y,nodes,boxes,prims"));
            let column = ["nodes", "boxes", "prims"]
                .iter()
                .position(|c| *c == counter)
                .unwrap();
            let rows: Vec<Vec<u64>> = lines
                .map(|line| line.split(',').map(|v| v.parse().unwrap()).collect())
                .collect();
            assert_eq!(rows.len(), 24 * 16);
            assert_eq!(rows.iter().map(|row| row[2 + column]).sum::<u64>(), total);
            assert_eq!(&rows[25][..2], &[1, 1]);
            let image = std::fs::read(&png).unwrap();
            assert_eq!(&image[1..4], b"PNG");
        }
    }
}

#[test]
fn heatmap_packets_show_what_a_packet_did_for_each_ray() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("contract-heatmap-packets");
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("map.png").to_string_lossy().into_owned();
    let total = |accel: &str, packet: &str| {
        let output = cli(&[
            "heatmap",
            "--accel",
            accel,
            "--camera",
            "40x24",
            "--counter",
            "boxes",
            "--packet",
            packet,
            "--out",
            &png,
            "--json",
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        let value: serde_json::Value = serde_json::from_str(stdout(&output).trim()).unwrap();
        assert_eq!(value["packet"].as_u64(), packet.parse().ok());
        value["total"].as_u64().unwrap()
    };
    // A wide BVH tests each box a packet reaches against all its active rays; a binary BVH
    // traces packets ray by ray, so its map does not change.
    assert_ne!(
        total("bvh8:sah-binned", "64"),
        total("bvh8:sah-binned", "1")
    );
    assert_eq!(total("bvh:sah-binned", "16"), total("bvh:sah-binned", "1"));
}

#[test]
fn heatmap_bad_input_leaves_no_file() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("contract-heatmap-bad");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("map.png").to_string_lossy().into_owned();
    let bad_mesh = file(
        "truncated-normal.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1\nf 1 2 3\n",
    );
    let missing_dir = dir
        .join("missing")
        .join("map.csv")
        .to_string_lossy()
        .into_owned();
    let small = ["--camera", "8x8"];
    let median = ["--accel", "bvh:median"];
    let cases: [(Vec<&str>, &str); 6] = [
        (
            [&median[..], &small, &["--packet", "8"]].concat(),
            "--packet 8: packets are square tiles of 1, 4, 16 or 64 pixels",
        ),
        (
            [&median[..], &small, &["--mesh", &bad_mesh]].concat(),
            "truncated-normal.obj:4: a normal needs 3 numbers",
        ),
        (
            [&median[..], &["--camera", "12"]].concat(),
            "'12' is not WIDTHxHEIGHT",
        ),
        (
            [&median[..], &small, &["--threads", "0"]].concat(),
            "--threads must be at least 1",
        ),
        ([&small[..], &["--accel", "bvh:nope"]].concat(), "bvh:nope"),
        (
            [&median[..], &small, &["--csv", &missing_dir]].concat(),
            "map.csv: cannot write the file",
        ),
    ];
    for (extra, expected) in cases {
        let mut args = vec!["heatmap", "--out", &png];
        args.extend_from_slice(&extra);
        assert_fails(&args, expected);
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert!(left.is_empty(), "{extra:?} left {left:?}");
    }
}

#[test]
fn quiz_json_has_the_fixed_fields_of_each_kind() {
    let fields: &[(&str, &[&str])] = &[
        ("slab", &["box", "ray"]),
        ("first-hit", &["shapes", "ray"]),
        ("visit-order", &["shapes", "ray", "order", "nodes"]),
        (
            "sah-split",
            &[
                "shapes",
                "node_box",
                "node_shapes",
                "axis",
                "cost",
                "candidates",
            ],
        ),
    ];
    for (kind, kind_fields) in fields {
        let output = cli(&[
            "quiz", "--kind", kind, "--seed", "3", "--count", "4", "--json",
        ]);
        assert!(output.status.success(), "{}", stderr(&output));
        let text = stdout(&output);
        assert_eq!(text.lines().count(), 4, "{text}");
        for (index, line) in text.lines().enumerate() {
            let question: serde_json::Value = serde_json::from_str(line).unwrap();
            assert_eq!(question["kind"], *kind);
            assert_eq!(question["seed"].as_u64(), Some(3 + index as u64));
            assert!(question["prompt"].is_string() && question.get("answer").is_some());
            for field in *kind_fields {
                assert!(
                    question.get(*field).is_some(),
                    "{kind} lacks {field}: {line}"
                );
            }
        }
    }
    // Each kind's answer fields.
    let answer = |kind: &str| {
        let output = cli(&[
            "quiz", "--kind", kind, "--seed", "1", "--json", "--level", "hard",
        ]);
        let question: serde_json::Value = serde_json::from_str(stdout(&output).trim()).unwrap();
        question["answer"].clone()
    };
    let slab = answer("slab");
    for field in ["hit", "t_enter", "t_exit", "enter_axis"] {
        assert!(slab.get(field).is_some(), "{slab}");
    }
    assert!(answer("first-hit").get("shape").is_some());
    assert!(answer("visit-order")["visited"].is_array());
    assert!(answer("sah-split")["costs"].is_array());
}

#[test]
fn quiz_text_is_for_print_and_mixes_kinds() {
    // One of each kind.
    let kinds = accelviz_quiz::kind_names().len().to_string();
    let output = cli(&["quiz", "--seed", "7", "--count", &kinds]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert_eq!(
        text.matches("Answer:").count(),
        text.matches("Why:").count()
    );
    for kind in accelviz_quiz::kind_names() {
        assert!(
            text.contains(&format!("[{kind} · seed")),
            "{kind} missing:\n{text}"
        );
    }
    // The same arguments, the same quiz.
    assert_eq!(
        stdout(&cli(&["quiz", "--seed", "7", "--count", &kinds])),
        text
    );
}

#[test]
fn quiz_errors_name_the_valid_choices() {
    assert_fails(
        &["quiz", "--kind", "slabs", "--seed", "1"],
        "unknown question kind 'slabs'; the kinds are: slab, first-hit, visit-order",
    );
    assert_fails(
        &["quiz", "--seed", "1", "--level", "expert"],
        "the levels are: easy, medium, hard",
    );
    assert_fails(
        &["quiz", "--seed", "-1"],
        "--seed: '-1' is not a whole number",
    );
    assert_fails(
        &["quiz", "--seed", "x1"],
        "--seed: 'x1' is not a whole number",
    );
    assert_fails(
        &["quiz", "--seed", "1", "--count", "0"],
        "--count: '0' is not a whole number from 1",
    );
    assert_fails(
        &["quiz", "--seed", "1", "--count", "many"],
        "--count: 'many' is not a whole number from 1",
    );
}

/// A 3D view's "copy as a ray-file line" (`accelviz_scene::rays::ray_line`) is read by
/// `query` as exactly that ray: on the teapot, in f64, the hit is brute force's, at its t.
#[test]
fn query_reads_a_copied_ray_line_as_the_same_ray() {
    use accelviz_core::{NoObserver, TraceOptions, TriangleSet, brute_force};
    use accelviz_scene::rays::{RaySpec, ray_line};
    use glam::DVec3;
    let mesh = (accelviz_scene::builtin::named("builtin:teapot")
        .unwrap()
        .make)();
    let triangles = TriangleSet::<DVec3>::from_f64(&mesh.triangles);
    // Rays as a camera gives them: an eye with many digits, directions of no round numbers.
    let eye = DVec3::new(
        std::f64::consts::E,
        std::f64::consts::SQRT_2,
        -std::f64::consts::PI,
    );
    let rays: Vec<RaySpec> = (0..40)
        .map(|k| {
            let k = f64::from(k);
            let target = DVec3::new(
                -1.5 + 0.0761 * k,
                0.3 + 0.0333 * (k * 0.7).sin(),
                0.1 * k.cos(),
            );
            RaySpec::generated(eye, (target - eye) * (1.0 + 1e-3 * k))
        })
        .collect();
    let text: String = rays.iter().map(|ray| ray_line(ray) + "\n").collect();
    let path = file("copied.rays", &text);
    let output = cli(&[
        "query",
        "--mesh",
        "builtin:teapot",
        "--accel",
        "kd:sah",
        "--precision",
        "f64",
        "--rays",
        &path,
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let mut hits = 0;
    for (ray, line) in rays.iter().zip(stdout(&output).lines()) {
        let expected = brute_force(
            &triangles,
            &ray.to_ray::<DVec3>().unwrap(),
            &TraceOptions::default(),
            &mut NoObserver,
        );
        match expected {
            Some(hit) => {
                hits += 1;
                let words: Vec<&str> = line.split(' ').collect();
                assert_eq!(words[..2], ["HIT", &hit.primitive.to_string()], "{line}");
                let t: f64 = words[2].parse().unwrap();
                assert!(
                    (t - hit.t).abs() <= 1e-9 * hit.t.abs(),
                    "{line} against t = {}",
                    hit.t
                );
            }
            None => assert_eq!(line, "MISS"),
        }
    }
    assert!(hits >= 10, "only {hits} of the rays hit the teapot");
}

/// What a person trying the CLI met: a bare `accelviz-cli` ran a benchmark silently (now
/// its usage), `--repeat 0` ran one round (now an error), an absurd camera aborted with a
/// backtrace (now one line), and the help left out built-in meshes and question kinds.
#[test]
fn the_cli_says_what_it_does_and_refuses_what_it_cannot() {
    let bare = cli(&[]);
    assert_eq!(bare.status.code(), Some(2));
    assert!(bare.stdout.is_empty());
    assert!(
        stderr(&bare).contains("Usage: accelviz-cli <COMMAND>"),
        "{}",
        stderr(&bare)
    );
    assert_fails(
        &[
            "bench",
            "--mesh",
            "builtin:cube",
            "--accel",
            "bvh:middle",
            "--repeat",
            "0",
        ],
        "at least one round",
    );
    assert_fails(
        &["tradeoff", "--mesh", "builtin:cube", "--repeat", "0"],
        "at least one round",
    );
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("huge.png");
    assert_fails(
        &[
            "heatmap",
            "--mesh",
            "builtin:cube",
            "--accel",
            "bvh:middle",
            "--camera",
            "100000x100000",
            "--out",
            &out.to_string_lossy(),
        ],
        "at most 16777216",
    );
    let sah = stdout(&cli(&["sah", "--help"]));
    for builtin in accelviz_scene::builtin::BUILTINS {
        assert!(sah.contains(builtin.name), "sah --help: {}", builtin.name);
    }
    let quiz = stdout(&cli(&["quiz", "--help"]));
    for kind in accelviz_quiz::kind_names() {
        assert!(quiz.contains(kind), "quiz --help: {kind}");
    }
    let tradeoff = stdout(&cli(&["tradeoff", "--help"]));
    assert!(
        tradeoff.contains("total-vs-rays.svg") && tradeoff.contains("sah-assumption.svg"),
        "{tradeoff}"
    );
    assert!(!tradeoff.contains("brute force"), "{tradeoff}");
}

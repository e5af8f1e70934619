//! The command line on real FMUs (dist/, dist/ssp/) and on archives and FMUs broken inside the
//! test from them: every bad input of the master gets one message naming the archive element,
//! component, variable, FMI function and time as far as they apply, a non-zero exit status, and
//! the rows before a failure stay in the output file. Needs `./scripts/run` (dist/).

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn dist(rel: &str) -> PathBuf {
    let p = repo().join("dist").join(rel);
    assert!(
        p.exists(),
        "{} is missing: run ./scripts/run first",
        p.display()
    );
    p
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fmi_master_cli_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `master run ARGS... --out DIR/out.csv`: (exit code, stdout, stderr, the CSV if written).
fn run(dir: &Path, args: &[&str]) -> (i32, String, String, Option<String>) {
    let out = dir.join("out.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_master"))
        .arg("run")
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let csv = std::fs::read_to_string(&out).ok();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        csv,
    )
}

/// A zip's entries.
fn entries(path: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut z = zip::ZipArchive::new(std::fs::File::open(path).unwrap()).unwrap();
    let mut out = BTreeMap::new();
    for i in 0..z.len() {
        let mut e = z.by_index(i).unwrap();
        let mut b = Vec::new();
        e.read_to_end(&mut b).unwrap();
        out.insert(e.name().unwrap().into_owned(), b);
    }
    out
}

fn write_zip(path: &Path, files: &BTreeMap<String, Vec<u8>>) {
    let mut z = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    for (name, bytes) in files {
        z.start_file(name.as_str(), zip::write::SimpleFileOptions::default())
            .unwrap();
        z.write_all(bytes).unwrap();
    }
    z.finish().unwrap();
}

/// dist/ssp/<scene>.ssp with `edit` applied to its entries, written to DIR/<scene>.ssp.
fn broken(dir: &Path, scene: &str, edit: impl FnOnce(&mut BTreeMap<String, Vec<u8>>)) -> PathBuf {
    let mut files = entries(&dist(&format!("ssp/{scene}.ssp")));
    edit(&mut files);
    let p = dir.join(format!("{scene}.ssp"));
    write_zip(&p, &files);
    p
}

fn replace(files: &mut BTreeMap<String, Vec<u8>>, entry: &str, from: &str, to: &str) {
    let text = String::from_utf8(files[entry].clone()).unwrap();
    assert!(text.contains(from), "{entry} has no '{from}'");
    files.insert(entry.to_string(), text.replacen(from, to, 1).into_bytes());
}

/// Asserts a failure whose one message line contains every piece.
fn fails(r: &(i32, String, String, Option<String>), pieces: &[&str]) {
    assert_ne!(r.0, 0, "exit status 0; stdout: {}", r.1);
    let msg: Vec<&str> = r.2.lines().filter(|l| l.starts_with("master: ")).collect();
    assert_eq!(msg.len(), 1, "one message expected, got: {}", r.2);
    // shown with --nocapture: the messages docs/master.md quotes
    eprintln!("{}", msg[0]);
    for p in pieces {
        assert!(msg[0].contains(p), "the message lacks '{p}': {}", msg[0]);
    }
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn every_archive_runs_and_writes_every_output() {
    let dir = scratch("ok");
    for scene in ["belt", "bounce", "puck0", "bushing_pendulum"] {
        let r = run(
            &dir,
            &[
                s(&dist(&format!("ssp/{scene}.ssp"))),
                "--method",
                "jacobi",
                "--step",
                "1e-3",
            ],
        );
        assert_eq!(r.0, 0, "{scene}: {}", r.2);
        let csv = r.3.unwrap();
        let header = csv.lines().next().unwrap();
        assert!(header.starts_with("time,"), "{header}");
        // the Body's position and the connector's loads are columns, component.variable
        let body = if scene == "bushing_pendulum" {
            "pendulum"
        } else if scene == "puck0" {
            "puck"
        } else {
            "mass"
        };
        assert!(header.contains(&format!(",{body}.r[1],")), "{header}");
        // the summary line: steps, FMI calls, CPU per simulated second
        assert!(
            r.1.contains(" steps of 0.001 s")
                && r.1.contains(" FMI calls, CPU ")
                && r.1.contains(" s per simulated second"),
            "{}",
            r.1
        );
        let rows = csv.lines().count() - 1;
        let steps: usize =
            r.1.split(": ")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap();
        assert_eq!(
            rows,
            steps + 1,
            "one row per communication point, t = 0 included"
        );
    }
}

#[test]
fn the_interval_samples_every_kth_point_on_exact_ticks() {
    let dir = scratch("interval");
    let r = run(
        &dir,
        &[
            s(&dist("ssp/bounce.ssp")),
            "--step",
            "1e-3",
            "--interval",
            "0.01",
        ],
    );
    assert_eq!(r.0, 0, "{}", r.2);
    let times: Vec<String> =
        r.3.unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap().to_string())
            .collect();
    assert_eq!(times.len(), 11);
    // t = k·H exactly: the 10th sample is 100 · 1e-3 as one product, not a sum of steps
    assert_eq!(times[10], format!("{:?}", 100.0 * 1e-3));
    let r = run(
        &dir,
        &[
            s(&dist("ssp/bounce.ssp")),
            "--step",
            "1e-3",
            "--interval",
            "0.0015",
        ],
    );
    fails(
        &r,
        &["the output interval 0.0015 is not a whole number of steps of 0.001"],
    );
}

#[test]
fn fmi3_fmus_run_alone_with_start_values() {
    let dir = scratch("fmi3");
    let r = run(
        &dir,
        &[
            s(&dist("fmi3/Body.fmu")),
            "--step",
            "0.01",
            "--stop",
            "0.1",
            "--start",
            "dof.r[3]=1",
            "--start",
            "gravity[3]=-9.81",
        ],
    );
    assert_eq!(r.0, 0, "{}", r.2);
    let csv = r.3.unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "r[3]")
        .expect("a lone FMU's columns are its variable names");
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    // free fall from rest under the zero-order hold: z(t) = −g t²/2 exactly per step (body.md)
    assert!(
        (last[col] - (-9.81 * 0.1 * 0.1 / 2.0)).abs() < 1e-12,
        "{}",
        last[col]
    );
}

#[test]
fn a_step_error_keeps_the_rows_before_it() {
    let dir = scratch("step_error");
    // a gravity of 1e307 overflows the Body's position at its sixth step: fmi2DoStep returns
    // fmi2Error at t = 5, after the rows at t = 0 … 5 (the connector holding its inputs, so that
    // its own extrapolated path does not overflow first)
    let r = run(
        &dir,
        &[
            s(&dist("ssp/bounce.ssp")),
            "--start",
            "mass.gravity[3]=1e307",
            "--start",
            "radialthrust.cosim.extrapolation=0",
            "--step",
            "1",
            "--stop",
            "20",
        ],
    );
    fails(
        &r,
        &[
            "component 'mass'",
            "fmi2DoStep at t = 5",
            "returned fmi2Error",
            "not finite",
            "the 6 rows before are in",
        ],
    );
    let csv = r.3.unwrap();
    let times: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(times, ["0.0", "1.0", "2.0", "3.0", "4.0", "5.0"]);
    // and those rows are the rows of the same run stopped before the failure
    let ok = run(
        &scratch("step_error_ok"),
        &[
            s(&dist("ssp/bounce.ssp")),
            "--start",
            "mass.gravity[3]=1e307",
            "--start",
            "radialthrust.cosim.extrapolation=0",
            "--step",
            "1",
            "--stop",
            "5",
        ],
    );
    assert_eq!(ok.0, 0, "{}", ok.2);
    assert_eq!(ok.3.unwrap(), csv);
}

#[test]
fn a_malformed_ssd_is_named_with_its_line() {
    let dir = scratch("malformed_ssd");
    let p = broken(&dir, "bounce", |f| {
        replace(
            f,
            "SystemStructure.ssd",
            "</ssd:Elements>",
            "</ssd:Element>",
        )
    });
    fails(
        &run(&dir, &[s(&p)]),
        &["SystemStructure.ssd", "not well-formed XML at line"],
    );
}

#[test]
fn an_ssd_invalid_under_ssp_1_0_is_refused() {
    let dir = scratch("invalid_ssd");
    let p = broken(&dir, "bounce", |f| {
        replace(
            f,
            "SystemStructure.ssd",
            "version=\"1.0\" name=\"bounce\"",
            "version=\"2.0\" name=\"bounce\"",
        )
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "SystemStructure.ssd line 2 <SystemStructureDescription>",
            "version '2.0' is not SSP 1.0",
        ],
    );
    let p = broken(&dir, "bounce", |f| {
        replace(f, "SystemStructure.ssd", " endConnector=\"f[3]\"", "")
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "SystemStructure.ssd line",
            "<Connection>",
            "the attribute endConnector is missing (SSP 1.0 requires it)",
        ],
    );
    let p = broken(&dir, "bounce", |f| {
        replace(f, "SystemStructure.ssd", "kind=\"input\"", "kind=\"inlet\"")
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "<Connector>",
            "component 'radialthrust'",
            "kind 'inlet' is not one of SSP 1.0's",
        ],
    );
}

#[test]
fn a_malformed_or_invalid_ssv_is_named() {
    let dir = scratch("ssv");
    let p = broken(&dir, "bushing_pendulum", |f| {
        replace(f, "resources/bushing.ssv", "</ssv:Parameters>", "")
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "resources/bushing.ssv",
            "component 'bushing'",
            "not well-formed XML",
        ],
    );
    let p = broken(&dir, "bushing_pendulum", |f| {
        replace(
            f,
            "resources/bushing.ssv",
            "<ssv:Real value=\"400.0\"/>",
            "<ssv:Real valu=\"400.0\"/>",
        )
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "resources/bushing.ssv",
            "component 'bushing'",
            "variable 'elasticity.k1'",
            "the attribute value is missing",
        ],
    );
    let p = broken(&dir, "bushing_pendulum", |f| {
        replace(
            f,
            "resources/bushing.ssv",
            "<ssv:Real value=\"400.0\"/>",
            "<ssv:Real value=\"stiff\"/>",
        )
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "resources/bushing.ssv line",
            "component 'bushing'",
            "variable 'elasticity.k1'",
            "'stiff' is not a number",
        ],
    );
}

#[test]
fn a_missing_fmu_variable_or_parameter_set_is_named() {
    let dir = scratch("missing");
    let p = broken(&dir, "bushing_pendulum", |f| {
        f.remove("resources/Bushing.fmu");
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "SystemStructure.ssd line",
            "<Component>",
            "component 'bushing'",
            "the FMU 'resources/Bushing.fmu' is missing from the archive",
        ],
    );
    let p = broken(&dir, "bushing_pendulum", |f| {
        f.remove("resources/bushing.ssv");
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "<ParameterBinding>",
            "component 'bushing'",
            "the parameter set 'resources/bushing.ssv' is missing from the archive",
        ],
    );
    let p = broken(&dir, "bushing_pendulum", |f| {
        replace(
            f,
            "resources/bushing.ssv",
            "name=\"elasticity.k1\"",
            "name=\"elasticity.kx\"",
        )
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "resources/bushing.ssv line",
            "component 'bushing'",
            "variable 'elasticity.kx'",
            "the parameter set names a variable resources/Bushing.fmu does not have",
        ],
    );
    let p = broken(&dir, "bushing_pendulum", |f| {
        let text = String::from_utf8(f["SystemStructure.ssd"].clone())
            .unwrap()
            .replace("\"b.r[1]\"", "\"b.r[9]\"");
        f.insert("SystemStructure.ssd".into(), text.into_bytes());
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "SystemStructure.ssd line",
            "component 'bushing'",
            "variable 'b.r[9]'",
            "resources/Bushing.fmu has no variable of this name",
        ],
    );
    fails(
        &run(&dir, &[s(&dir.join("nothing.ssp"))]),
        &["nothing.ssp", "no such file"],
    );
    fails(
        &run(
            &dir,
            &[s(&dist("ssp/bounce.ssp")), "--start", "mass.gravity[4]=1"],
        ),
        &[
            "--start",
            "variable 'mass.gravity[4]'",
            "no component has this variable",
        ],
    );
}

#[test]
fn two_connections_into_one_input_are_refused() {
    let dir = scratch("two_into_one");
    let p = broken(&dir, "bushing_pendulum", |f| {
        replace(f, "SystemStructure.ssd", "</ssd:Connections>", "  <ssd:Connection startElement=\"bushing\" startConnector=\"b.f[2]\" endElement=\"pendulum\" endConnector=\"f[1]\"/>\n    </ssd:Connections>")
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "SystemStructure.ssd line",
            "component 'pendulum'",
            "variable 'f[1]'",
            "two connections lead into this input",
        ],
    );
}

#[test]
fn a_type_or_causality_mismatch_is_refused() {
    let dir = scratch("mismatch");
    // the connector's Integer output event.count into the Body's Real input f[1]
    let p = broken(&dir, "bounce", |f| {
        replace(f, "SystemStructure.ssd", "</ssd:Connections>", "  <ssd:Connection startElement=\"radialthrust\" startConnector=\"event.count\" endElement=\"mass\" endConnector=\"f[1]\"/>\n    </ssd:Connections>")
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "SystemStructure.ssd line",
            "component 'mass'",
            "variable 'f[1]'",
            "radialthrust.event.count (Int32) to mass.f[1] (Float64): the types differ",
        ],
    );
    // a connection starting at an input
    let p = broken(&dir, "bounce", |f| {
        replace(f, "SystemStructure.ssd", "</ssd:Connections>", "  <ssd:Connection startElement=\"mass\" startConnector=\"f[1]\" endElement=\"radialthrust\" endConnector=\"a.r[1]\"/>\n    </ssd:Connections>")
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "component 'mass'",
            "variable 'f[1]'",
            "a connection starts at mass.f[1], whose causality is input, not output",
        ],
    );
    // the SSD's declared kind and type against the FMU's
    let p = broken(&dir, "bounce", |f| {
        replace(
            f,
            "SystemStructure.ssd",
            "name=\"f[3]\" kind=\"input\"",
            "name=\"f[3]\" kind=\"output\"",
        )
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "<Connector>",
            "component 'mass'",
            "variable 'f[3]'",
            "the SSD declares it output, resources/Body.fmu declares it input",
        ],
    );
}

#[test]
fn a_zip_entry_leaving_the_folder_is_refused() {
    let dir = scratch("zip_slip");
    let p = broken(&dir, "bounce", |f| {
        f.insert("../../escaped.txt".into(), b"x".to_vec());
    });
    fails(&run(&dir, &[s(&p)]), &["bounce.ssp", "the zip entry '../../escaped.txt' would leave the extraction folder: it goes up with '..'"]);
    assert!(!std::env::temp_dir().join("escaped.txt").exists());
    // inside an FMU inside the archive: named by its path in the archive
    let p = broken(&dir, "bounce", |f| {
        let mut fmu = BTreeMap::new();
        let tmp = dir.join("Body.fmu");
        std::fs::write(&tmp, &f["resources/Body.fmu"]).unwrap();
        fmu.extend(entries(&tmp));
        fmu.insert("/abs/evil.so".into(), b"x".to_vec());
        write_zip(&tmp, &fmu);
        f.insert("resources/Body.fmu".into(), std::fs::read(&tmp).unwrap());
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "resources/Body.fmu",
            "component 'mass'",
            "the zip entry '/abs/evil.so' would leave the extraction folder: it is absolute",
        ],
    );
}

#[test]
fn an_fmu_that_fails_to_load_or_instantiate_is_named() {
    let dir = scratch("load");
    let mut fmu = entries(&dist("Bushing.fmu"));
    fmu.insert(
        "binaries/linux64/Bushing.so".into(),
        b"not a library".to_vec(),
    );
    let bad = dir.join("Bushing.fmu");
    write_zip(&bad, &fmu);
    fails(
        &run(&dir, &[s(&bad), "--step", "1e-3"]),
        &["Bushing.fmu", "cannot load", "Bushing.so"],
    );
    let p = broken(&dir, "bushing_pendulum", |f| {
        f.insert("resources/Bushing.fmu".into(), std::fs::read(&bad).unwrap());
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "resources/Bushing.fmu",
            "component 'bushing'",
            "cannot load",
        ],
    );
    // a GUID the binary does not know: fmi2Instantiate refuses
    let mut fmu = entries(&dist("Bushing.fmu"));
    let md = String::from_utf8(fmu["modelDescription.xml"].clone()).unwrap();
    let guid_at = md.find("guid=\"").unwrap() + 6;
    let md = format!(
        "{}{{00000000-0000-0000-0000-000000000000}}{}",
        &md[..guid_at],
        &md[md[guid_at..].find('"').unwrap() + guid_at..]
    );
    fmu.insert("modelDescription.xml".into(), md.into_bytes());
    let p = broken(&dir, "bushing_pendulum", |f| {
        let tmp = dir.join("guid.fmu");
        write_zip(&tmp, &fmu);
        f.insert("resources/Bushing.fmu".into(), std::fs::read(&tmp).unwrap());
    });
    fails(
        &run(&dir, &[s(&p)]),
        &[
            "resources/Bushing.fmu",
            "component 'bushing'",
            "fmi2Instantiate",
            "returned NULL",
            "at t = 0",
        ],
    );
}

#[test]
fn a_bad_start_value_is_named() {
    let dir = scratch("start");
    fails(
        &run(
            &dir,
            &[
                s(&dist("Body.fmu")),
                "--step",
                "1e-3",
                "--start",
                "mass=heavy",
            ],
        ),
        &["--start", "variable 'mass'", "'heavy' is not a number"],
    );
    fails(
        &run(
            &dir,
            &[s(&dist("Body.fmu")), "--step", "1e-3", "--start", "r[1]=1"],
        ),
        &[
            "--start",
            "variable 'r[1]'",
            "its causality is output and it cannot be set",
        ],
    );
    // a value the FMU itself refuses: its fmi2SetReal, at t = 0
    fails(
        &run(
            &dir,
            &[s(&dist("Body.fmu")), "--step", "1e-3", "--start", "mass=-1"],
        ),
        &[
            "--start",
            "component 'Body'",
            "variable 'mass'",
            "fmi2SetReal at t = 0",
            "returned fmi2Error",
        ],
    );
}

#[test]
fn gauss_seidel_reports_an_algebraic_loop_by_name() {
    let dir = scratch("loop");
    // two Bushings whose node-b forces feed each other's node-b position: each force depends
    // directly on its position (feedthrough), so the loop has no component to start from
    let ssd = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="1.0" name="loop">
  <ssd:System name="loop">
    <ssd:Elements>
      <ssd:Component name="one" source="resources/Bushing.fmu"/>
      <ssd:Component name="two" source="resources/Bushing.fmu"/>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="one" startConnector="b.f[1]" endElement="two" endConnector="b.r[1]"/>
      <ssd:Connection startElement="two" startConnector="b.f[1]" endElement="one" endConnector="b.r[1]">
        <ssc:LinearTransformation factor="1e-3" offset="0"/>
      </ssd:Connection>
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="0.01"/>
</ssd:SystemStructureDescription>"#;
    let mut files = BTreeMap::new();
    files.insert("SystemStructure.ssd".to_string(), ssd.as_bytes().to_vec());
    files.insert(
        "resources/Bushing.fmu".to_string(),
        std::fs::read(dist("Bushing.fmu")).unwrap(),
    );
    let p = dir.join("loop.ssp");
    write_zip(&p, &files);
    fails(
        &run(&dir, &[s(&p), "--method", "gauss_seidel", "--step", "1e-3"]),
        &[
            "algebraic loop: ",
            "one.b.r[1] → one.b.f[1] → two.b.r[1] → two.b.f[1] → one.b.r[1]",
        ],
    );
    // Jacobi needs no order: it runs
    let r = run(&dir, &[s(&p), "--method", "jacobi", "--step", "1e-3"]);
    assert_eq!(r.0, 0, "{}", r.2);
}

#[test]
fn bad_arguments_get_the_usage() {
    let dir = scratch("args");
    let r = run(&dir, &[s(&dist("ssp/bounce.ssp")), "--method", "newton"]);
    assert_eq!(r.0, 2);
    assert!(
        r.2.contains("unknown method 'newton'; there are: jacobi, gauss_seidel"),
        "{}",
        r.2
    );
    let r = run(&dir, &[s(&dist("ssp/bounce.ssp")), "--step", "0.3"]);
    fails(
        &r,
        &["the step 0.3 does not divide the time from 0 to 0.1 into whole steps"],
    );
}

#[test]
fn nested_systems_inline_parameter_sets_and_linear_transformations() {
    let dir = scratch("nested");
    // src moves at 1 m/s along z (prescribed): r(t_k) = k·h. Its r[3] reaches dst.f[3] through
    // the nested system's connector `load`, y = 0.5·(2·r + 0.5) + 1 = r + 1.25 (two linear
    // transformations composed). dst is a free unit mass without gravity: under Jacobi its
    // velocity after n steps is Σ_(k<n) (k·h + 1.25)·h (body.md: v += f/m·h per step).
    let set = |body: &str| {
        format!(
            r#"<ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>
              <ssv:ParameterSet version="1.0" name="p"><ssv:Parameters>{body}</ssv:Parameters></ssv:ParameterSet>
            </ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>"#
        )
    };
    let real = |n: &str, v: &str| {
        format!(r#"<ssv:Parameter name="{n}"><ssv:Real value="{v}"/></ssv:Parameter>"#)
    };
    let int = |n: &str, v: &str| {
        format!(r#"<ssv:Parameter name="{n}"><ssv:Integer value="{v}"/></ssv:Parameter>"#)
    };
    let src = set(&format!(
        "{}{}{}",
        int("dof.r[3]", "2"),
        real("start.v[3]", "1.0"),
        real("gravity[3]", "0")
    ));
    let dst = set(&format!(
        "{}{}",
        real("mass", "1.0"),
        real("gravity[3]", "0")
    ));
    let ssd = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="nested">
  <ssd:System name="outer">
    <ssd:Elements>
      <ssd:Component name="src" source="resources/Body.fmu">{src}</ssd:Component>
      <ssd:System name="sub">
        <ssd:Connectors><ssd:Connector name="load" kind="input"><ssc:Real/></ssd:Connector></ssd:Connectors>
        <ssd:Elements><ssd:Component name="dst" source="resources/Body.fmu">{dst}</ssd:Component></ssd:Elements>
        <ssd:Connections>
          <ssd:Connection startConnector="load" endElement="dst" endConnector="f[3]">
            <ssc:LinearTransformation factor="0.5" offset="1"/>
          </ssd:Connection>
        </ssd:Connections>
      </ssd:System>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="src" startConnector="r[3]" endElement="sub" endConnector="load">
        <ssc:LinearTransformation factor="2" offset="0.5"/>
      </ssd:Connection>
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="1"/>
</ssd:SystemStructureDescription>"#
    );
    let mut files = BTreeMap::new();
    files.insert("SystemStructure.ssd".to_string(), ssd.into_bytes());
    files.insert(
        "resources/Body.fmu".to_string(),
        std::fs::read(dist("Body.fmu")).unwrap(),
    );
    let p = dir.join("nested.ssp");
    write_zip(&p, &files);
    let r = run(&dir, &[s(&p), "--step", "0.1"]);
    assert_eq!(r.0, 0, "{}", r.2);
    let csv = r.3.unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name}: {header:?}"))
    };
    let (v, z) = (col("sub.dst.v[3]"), col("src.r[3]"));
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let h = 0.1;
    let mut expected = 0.0;
    for (k, row) in rows.iter().enumerate() {
        // 1e-12: sums of ten terms of order 0.1 computed in another order than the FMU's
        assert!(
            (row[v] - expected).abs() < 1e-12,
            "t = {}: v = {}, expected {expected}",
            row[0],
            row[v]
        );
        assert!((row[z] - k as f64 * h).abs() < 1e-12);
        expected += (k as f64 * h + 1.25) * h;
    }
    assert_eq!(rows.len(), 11);
    assert!((rows[10][v] - 1.7).abs() < 1e-12, "{}", rows[10][v]);
}

//! The bundled recordings derived from real data are exactly the raw numbers in SI units.

use std::path::PathBuf;
use stoss::input::recording;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

fn raw_table(path: &std::path::Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * b.abs().max(1e-12)
}

#[test]
fn taylor_recordings_are_the_published_numbers() {
    // GOAL: Lf, Df and W of each Taylor recording equal StJohnson.dat (SI).
    // SETUP: fixtures/real/4340-taylor/StJohnson.dat lines 1, 4, 7 (columns 6, 10, 11).
    // REFERENCE: the raw file; 1e-6 relative (6 significant digits written).
    let raw = raw_table(&fixtures().join("real/4340-taylor/StJohnson.dat"));
    for (line, velocity) in [(0, 208), (3, 282), (6, 343)] {
        let row = &raw[line];
        let points =
            recording::load(&fixtures().join(format!("experiments/taylor-4340-{velocity}.csv")))
                .unwrap();
        let value = |quantity: &str| {
            points
                .iter()
                .find(|p| p.quantity == quantity)
                .unwrap()
                .value
        };
        assert!(close(value("final_length"), row[5]));
        assert!(close(value("footprint_diameter"), row[9]));
        let w = points.iter().find(|p| p.quantity == "diameter").unwrap();
        assert!(close(w.value, row[10]) && close(w.position, 0.2 * row[4]));
    }
}

#[test]
fn flow_recordings_are_the_published_numbers() {
    // GOAL: every flow-curve recording is its raw .dat in SI (percent strain -> strain for
    //       Lee-Yeh, MPa -> Pa).
    // REFERENCE: fixtures/real/4340-flow/*.dat, 1e-6 relative.
    let mut checked = 0;
    for entry in std::fs::read_dir(fixtures().join("real/4340-flow")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.ends_with(".dat") {
            continue;
        }
        let percent = name.ends_with("LY.dat");
        let raw = raw_table(&path);
        let recording_name = std::fs::read_dir(fixtures().join("experiments"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| {
                p.extension().is_some_and(|e| e == "toml")
                    && std::fs::read_to_string(p).unwrap().contains(&name)
            })
            .unwrap();
        let csv = recording_name.with_extension("csv");
        let points = recording::load(&csv).unwrap();
        assert_eq!(points.len(), raw.len(), "{name}");
        for (point, row) in points.iter().zip(&raw) {
            let strain = if percent { row[0] / 100.0 } else { row[0] };
            assert!(
                close(point.position, strain.max(0.0))
                    || (strain.abs() < 1e-9 && point.position == 0.0),
                "{name}"
            );
            assert!(close(point.value, row[1] * 1e6), "{name}");
        }
        checked += 1;
    }
    assert_eq!(checked, 10);
}

#[test]
fn every_bundled_experiment_passes_its_input_checks() {
    // GOAL: the up-front size and unit checks refuse no bundled experiment.
    // SETUP: every fixtures/experiments/*.toml, loaded (parsed, validated, recording read).
    // REFERENCE: Experiment::load succeeds for each.
    let mut count = 0;
    for entry in std::fs::read_dir(fixtures().join("experiments")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) == Some("toml") {
            if let Err(error) = stoss::experiment::Experiment::load(&path) {
                panic!("{}: {error}", path.display());
            }
            count += 1;
        }
    }
    assert!(count >= 20, "{count} experiments");
}

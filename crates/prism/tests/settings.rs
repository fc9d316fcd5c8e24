//! The settings table (`prism::options::SETTINGS`) is the one list of render settings:
//! docs/scene-format.md's `[render]` table names the same keys in the same order, with
//! the table's type and default, and a scene file's `[render]` table reads through it.

use prism::options::{SettingKind, SETTINGS};
use prism::RenderOptions;

/// The rows of docs/scene-format.md's `[render]` table: key, type and default cells.
fn documented_rows() -> Vec<(String, String, String)> {
    let doc = std::fs::read_to_string("../../docs/scene-format.md").unwrap();
    let section = doc
        .split("## `[render]`")
        .nth(1)
        .and_then(|rest| rest.split("\n## ").next())
        .expect("docs/scene-format.md has a [render] section");
    section
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            (
                cells[1].trim_matches('`').to_string(),
                cells[2].to_string(),
                cells[3].to_string(),
            )
        })
        .collect()
}

#[test]
fn the_scene_format_documents_every_setting_as_the_table_says() {
    let rows = documented_rows();
    let keys: Vec<&str> = rows.iter().map(|(k, _, _)| k.as_str()).collect();
    let table: Vec<&str> = SETTINGS.iter().map(|s| s.key).collect();
    assert_eq!(
        keys, table,
        "docs/scene-format.md's [render] rows differ from the settings table"
    );
    for (s, (key, kind, default)) in SETTINGS.iter().zip(&rows) {
        assert_eq!(kind, s.kind.type_name(), "{key}: type");
        // Numbers are documented as fractions or per filter; the others as written.
        let written = match s.kind {
            SettingKind::Number { .. } => continue,
            SettingKind::Name(_) | SettingKind::Spec => format!("`\"{}\"`", s.default_text()),
            _ => format!("`{}`", s.default_text()),
        };
        assert!(
            default.contains(&written),
            "{key}: the documented default {default} is not {written}"
        );
    }
}

/// Every key of the table is a key of the scene file's `[render]` table: a file that sets
/// each to a value of its own loads into the options the table's `set` gives.
#[test]
fn every_setting_reads_from_a_scene_file_as_set_gives_it() {
    let values = [
        ("width", "33"),
        ("height", "21"),
        ("samples", "3"),
        ("sampler", "jittered"),
        ("filter", "tent"),
        ("filter_radius", "1.5"),
        ("adaptive_threshold", "0.25"),
        ("adaptive_depth", "2"),
        ("adaptive_rule", "corners"),
        ("adaptive_jitter", "0.5"),
        ("adaptive_texture_spp", "9"),
        ("transfer", "display"),
        ("integrator", "path"),
        ("max_depth", "7"),
        ("min_weight", "0.125"),
        ("area_samples", "4"),
        ("spd_rules", "true"),
        ("threads", "2"),
        ("seed", "99"),
        ("accel", "bvh:leaf=4"),
        ("shadows", "light-buffer:res=20"),
        ("tile_size", "9"),
        ("packets", "false"),
        ("wavefront", "false"),
    ];
    let keys: Vec<&str> = values.iter().map(|(k, _)| *k).collect();
    let table: Vec<&str> = SETTINGS.iter().map(|s| s.key).collect();
    assert_eq!(keys, table, "this test names every setting");
    let mut expected = RenderOptions::default();
    let mut file = String::from("[render]\n");
    for (s, (key, text)) in SETTINGS.iter().zip(values) {
        expected.set(key, text).unwrap();
        assert_eq!((s.get)(&expected), text, "{key}");
        let value = match s.kind {
            SettingKind::Name(_) | SettingKind::Spec => format!("\"{text}\""),
            _ => text.to_string(),
        };
        file.push_str(&format!("{key} = {value}\n"));
    }
    file.push_str("[camera]\neye = [0, 0, 5]\n[[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n");
    let dir = std::env::temp_dir().join(format!("prism-settings-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("every-setting.toml");
    std::fs::write(&path, &file).unwrap();
    let loaded = prism_io::scene::load(&path);
    std::fs::remove_dir_all(&dir).unwrap();
    let scene = loaded.unwrap_or_else(|e| panic!("{e}\n{file}"));
    assert_eq!(scene.options, expected);
}

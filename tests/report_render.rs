//! Template rendering and atomic output directories.

use nanobeam::report::render::{render_template, write_dir_atomically, write_file_atomically};
use nanobeam::report::ReportError;
use serde_json::json;
use std::fs;

#[test]
fn renders_with_inheritance_between_files_of_the_directory() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("base.md"), "# {{ title }}\n{% block body %}{% endblock body %}").unwrap();
    fs::create_dir(dir.path().join("parts")).unwrap();
    fs::write(dir.path().join("parts/row.md"), "- {{ item }}\n").unwrap();
    fs::write(
        dir.path().join("report.md"),
        "{% extends \"base.md\" %}{% block body %}{% for item in items %}{% include \"parts/row.md\" %}{% endfor %}{% endblock body %}",
    )
    .unwrap();
    let out = render_template(dir.path(), "report.md", &json!({"title": "Case 1A", "items": ["a", "b"]})).unwrap();
    assert_eq!(out, "# Case 1A\n- a\n- b\n");
}

#[test]
fn syntax_error_names_the_broken_file() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("good.md"), "ok {{ x }}").unwrap();
    fs::write(dir.path().join("broken.md"), "{% if %}").unwrap();
    let err = render_template(dir.path(), "good.md", &json!({"x": 1})).unwrap_err();
    match &err {
        ReportError::Template { file, .. } => assert_eq!(file, &dir.path().join("broken.md")),
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("broken.md"), "{err}");
}

#[test]
fn render_error_names_the_template_and_the_missing_variable() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("table.md"), "{{ missing_value }}").unwrap();
    let err = render_template(dir.path(), "table.md", &json!({})).unwrap_err().to_string();
    assert!(err.contains("table.md") && err.contains("missing_value"), "{err}");
    let err = render_template(dir.path(), "absent.md", &json!({})).unwrap_err().to_string();
    assert!(err.contains("absent.md"), "{err}");
    let err = render_template(dir.path(), "table.md", &json!([1, 2])).unwrap_err().to_string();
    assert!(err.contains("table.md"), "{err}");
}

#[test]
fn atomic_dir_replaces_on_success_and_leaves_old_dir_untouched_on_failure() {
    let root = tempfile::tempdir().unwrap();
    let dest = root.path().join("out");
    write_dir_atomically::<ReportError>(&dest, |d| {
        fs::write(d.join("a.txt"), "v1").map_err(|e| ReportError::Io { path: d.join("a.txt"), source: e })
    })
    .unwrap();
    assert_eq!(fs::read_to_string(dest.join("a.txt")).unwrap(), "v1");

    // A failing build after writing some files: dest keeps v1, no partial files, no leftovers.
    let res = write_dir_atomically::<ReportError>(&dest, |d| {
        fs::write(d.join("a.txt"), "v2").unwrap();
        fs::write(d.join("partial.txt"), "x").unwrap();
        Err(ReportError::Drawing("simulated failure".into()))
    });
    assert!(res.is_err());
    assert_eq!(fs::read_to_string(dest.join("a.txt")).unwrap(), "v1");
    assert!(!dest.join("partial.txt").exists());
    let names: Vec<_> = fs::read_dir(root.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, vec![std::ffi::OsString::from("out")], "temporary directories left behind");

    // A panicking build also leaves dest and no temporary directory.
    let caught = std::panic::catch_unwind(|| {
        let _ = write_dir_atomically::<ReportError>(&dest, |_| panic!("boom"));
    });
    assert!(caught.is_err());
    assert_eq!(fs::read_to_string(dest.join("a.txt")).unwrap(), "v1");
    assert_eq!(fs::read_dir(root.path()).unwrap().count(), 1);

    // Success replaces the whole content (old files gone).
    write_dir_atomically::<ReportError>(&dest, |d| {
        fs::write(d.join("b.txt"), "v3").map_err(|e| ReportError::Io { path: d.join("b.txt"), source: e })
    })
    .unwrap();
    assert!(!dest.join("a.txt").exists());
    assert_eq!(fs::read_to_string(dest.join("b.txt")).unwrap(), "v3");
    assert_eq!(fs::read_dir(root.path()).unwrap().count(), 1);
}

#[test]
fn atomic_file_write_replaces_content() {
    let root = tempfile::tempdir().unwrap();
    let p = root.path().join("fig.svg");
    write_file_atomically(&p, b"<svg/>").unwrap();
    write_file_atomically(&p, b"<svg></svg>").unwrap();
    assert_eq!(fs::read_to_string(&p).unwrap(), "<svg></svg>");
    assert_eq!(fs::read_dir(root.path()).unwrap().count(), 1);
    let missing_parent = root.path().join("no/such/dir/f.svg");
    assert!(matches!(write_file_atomically(&missing_parent, b"x"), Err(ReportError::Io { .. })));
}

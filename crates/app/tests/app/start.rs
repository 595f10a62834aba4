//! Started without a display, the desktop app says so in one line, with where to go instead,
//! rather than a debug dump of the windowing library's error.

#[test]
fn without_a_display_the_app_says_so_in_one_line() {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_accelviz"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .expect("the app starts");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    for part in ["needs a display", "browser", "accelviz-cli"] {
        assert!(stderr.contains(part), "{stderr}");
    }
    assert!(!stderr.contains("OsError"), "no debug dump: {stderr}");
    assert!(output.stdout.is_empty());
}

//! One rule for tests whose prerequisite is missing (a Vulkan device, `../shared/meshes`):
//! on a developer's machine they say `SKIPPED` and return; under `CI=true` a skip is never a
//! silent pass, so the test fails with a message naming what is missing.

/// Reports that a test cannot run because `what` is missing: panics under `CI=true`,
/// prints `SKIPPED: ...` otherwise.
pub fn skipped(what: &str) {
    if std::env::var("CI").is_ok_and(|v| v == "true" || v == "1") {
        panic!("{what}; CI=true requires it (a skipped test is not a pass)");
    }
    println!("SKIPPED: {what}");
}

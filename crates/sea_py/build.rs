//! Lets `cargo test --workspace` run sea_py's test binary against a Python whose libpython is
//! not on the loader path (pyenv, conda): outside the wheel (feature `extension-module` off)
//! the binary links libpython, so it gets an rpath to the interpreter's `LIBDIR`. The wheel
//! (maturin, feature on) links no libpython and gets no rpath.

use std::process::Command;

fn main() {
    println!("cargo:rerun-if-env-changed=PYO3_PYTHON");
    println!("cargo:rerun-if-env-changed=VIRTUAL_ENV");
    println!("cargo:rerun-if-env-changed=PATH");
    println!("cargo:rerun-if-env-changed=PYO3_BUILD_EXTENSION_MODULE");
    // maturin sets PYO3_BUILD_EXTENSION_MODULE too, so a wheel built without our feature
    // gets no rpath either.
    let extension_module = std::env::var_os("CARGO_FEATURE_EXTENSION_MODULE").is_some()
        || std::env::var_os("PYO3_BUILD_EXTENSION_MODULE").is_some();
    let unix = std::env::var("CARGO_CFG_TARGET_FAMILY").is_ok_and(|family| family == "unix");
    if extension_module || !unix {
        return;
    }
    // The same interpreter pyo3's build script picks: PYO3_PYTHON, else python3 on PATH.
    let python = std::env::var("PYO3_PYTHON").unwrap_or_else(|_| "python3".to_string());
    let output = Command::new(python)
        .args([
            "-c",
            "import sysconfig; print(sysconfig.get_config_var('LIBDIR') or '')",
        ])
        .output();
    if let Ok(output) = output {
        let lib_dir = String::from_utf8_lossy(&output.stdout).trim().to_string();
        if output.status.success() && !lib_dir.is_empty() {
            println!("cargo:rustc-link-arg=-Wl,-rpath,{lib_dir}");
        }
    }
}

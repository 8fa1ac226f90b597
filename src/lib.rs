//! Test-only package: the workspace-level tests live in `tests/`.

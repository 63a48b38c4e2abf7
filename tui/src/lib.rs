//! OmniAD terminal UI. Work in progress (issue 5).

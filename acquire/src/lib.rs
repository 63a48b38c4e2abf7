//! OmniAD acquisition (paper §5-6): recording sets -> coefficient files. Work in progress (issue 3).

//! Block generation: a domain cut by joint planes and joint sets. (Being written.)

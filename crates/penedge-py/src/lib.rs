//! Python bindings of penedge (filled in next).

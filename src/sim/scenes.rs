//! scenes (todo)

//! Generated coefficient tables (see codegen/).

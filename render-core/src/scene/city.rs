//! The built-in city generator. STUB.

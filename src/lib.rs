pub use relief_dsl as dsl;

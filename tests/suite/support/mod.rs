pub mod prony;

//! Tests of the Siemens 840D additions and the thread cycles.

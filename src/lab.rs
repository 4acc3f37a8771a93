//! The lab: experiments of many runs of one drive (feature `lab`).

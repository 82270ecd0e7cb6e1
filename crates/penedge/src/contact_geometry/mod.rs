//! Contact geometry for mechanics: normal, contact points or polygon, area, signed distance.
//! (Being written.)

// The seeded pseudo-random generator of the corpus draw: mulberry32 (Tommy Ettinger's 32-bit generator,
// public domain), which is small, fast and identical on every JavaScript engine because it only uses
// 32-bit integer arithmetic (Math.imul and unsigned shifts).
//
// state_{k+1} = state_k + 0x6D2B79F5 (mod 2^32); the output is a bijective mix of the new state, divided
// by 2^32 to give a double in [0, 1). The seed is the initial state (taken mod 2^32).
"use strict";

function mulberry32(seed) {
  let a = seed >>> 0;
  return function next() {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

/** A uniform integer in [0, n) from one draw of `rand` (floor(u · n); n ≤ 2^32, so the bias is below n / 2^32). */
function randInt(rand, n) {
  if (!(n >= 1)) throw new Error(`randInt: n must be at least 1, got ${n}`);
  return Math.floor(rand() * n);
}

module.exports = { mulberry32, randInt };

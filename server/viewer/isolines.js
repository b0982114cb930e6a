// Isolux lines of a probe grid by marching squares, for the browser: the same rules as
// server/isolines.h (which draws them on `lambert render --probe-grid` maps), checked against it by
// tests/viewer_scale_test.mjs. On each cell the crossings of the level on its four edges, by linear
// interpolation along the edge, are joined into segments; a saddle cell (opposite corners on the
// same side) is resolved by the mean of its corners.

// `values` holds nu × nv samples, u fastest; sample (i, j) sits at lattice point (i, j). Returns
// segments [[x0, y0], [x1, y1]] in lattice coordinates. Cells with a non-finite corner are skipped.
export function isolines(values, nu, nv, level) {
  if (!(nu >= 1 && nv >= 1) || values.length !== nu * nv) throw new Error("isolines: expected nu × nv values");
  const out = [];
  const at = (i, j) => values[j * nu + i];
  for (let j = 0; j + 1 < nv; ++j) {
    for (let i = 0; i + 1 < nu; ++i) {
      // Corners counter-clockwise from (i, j); edge k runs from corner k to corner k + 1.
      const p = [[i, j], [i + 1, j], [i + 1, j + 1], [i, j + 1]];
      const v = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
      if (!v.every(Number.isFinite)) continue;
      const above = v.map((x) => x >= level);
      const crossing = [];
      const crosses = [];
      for (let k = 0; k < 4; ++k) {
        const n = (k + 1) % 4;
        crosses[k] = above[k] !== above[n];
        if (!crosses[k]) continue;
        const t = (level - v[k]) / (v[n] - v[k]);
        crossing[k] = [p[k][0] + t * (p[n][0] - p[k][0]), p[k][1] + t * (p[n][1] - p[k][1])];
      }
      const edges = [0, 1, 2, 3].filter((k) => crosses[k]);
      if (edges.length === 2) {
        out.push([crossing[edges[0]], crossing[edges[1]]]);
      } else if (edges.length === 4) {
        // Cut off the two corners on the other side from the centre: corner k lies between edges
        // k − 1 and k.
        const centreAbove = (v[0] + v[1] + v[2] + v[3]) / 4 >= level;
        for (let k = 0; k < 4; ++k) if (above[k] !== centreAbove) out.push([crossing[(k + 3) % 4], crossing[k]]);
      }
    }
  }
  return out;
}

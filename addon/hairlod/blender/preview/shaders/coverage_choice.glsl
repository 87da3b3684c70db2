/* Hair thinner than its drawn lines or strips, drawn by the share of them it covers (stochastic
 * transparency, Enderton et al. 2010, per strand or thick hair instead of per fragment): each item is
 * drawn whole, with the probability of its coverage, so that the expected coverage of every pixel,
 * 1 - prod(1 - c_i) over the items crossing it, is the hair's, with no sorting and no discard
 * (strand.vert.glsl, thick_hair.vert.glsl). An item's choice holds from frame to frame. The hair
 * layer's later samples at rest (frame.viewport.z = k > 0) move the item's number u along the circle
 * by k times the golden ratio: the points u + k phi (mod 1) spread evenly for any count of samples
 * (the three-distance theorem), so over S samples an item is drawn in c S of them within about one,
 * where independent choices would leave a spread of sqrt(c (1 - c) S), and a pixel's mean converges
 * faster. */

/* A uniform number in [0, 1) per integer (an integer hash: xor-shifts and odd multipliers). */
float unit_hash(uint x)
{
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return float(x >> 8) * (1.0 / 16777216.0);
}

/* Whether item `item` (a strand, or a thick hair of the level drawn) is drawn in this sample of the hair
 * layer, given the share of its drawn width that it covers. */
bool drawn_by_coverage(uint item, float coverage)
{
  return fract(unit_hash(item) + frame.viewport.z * 0.6180339887) < coverage;
}

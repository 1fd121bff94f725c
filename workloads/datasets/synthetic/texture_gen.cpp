#include "workloads/datasets/synthetic/texture_gen.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace edx::synthetic {
namespace {

/// Calls fn(offset) for the nine periodic copies of a shape so that drawings tile seamlessly.
template <class Fn>
void draw_wrapped(int size, Fn&& fn) {
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) fn(cv::Point(dx * size, dy * size));
  }
}

cv::Scalar gray(double value) { return cv::Scalar(std::clamp(value, 0.0, 255.0)); }

/// Tileable value noise: a cells x cells grid of uniform values, periodically padded and
/// upsampled with bicubic interpolation to size x size. CV_32FC1, roughly [0, 1].
cv::Mat value_noise(Rng& rng, int size, int cells) {
  cells = std::clamp(cells, 1, size);
  cv::Mat grid(cells, cells, CV_32FC1);
  for (int y = 0; y < cells; ++y) {
    for (int x = 0; x < cells; ++x) grid.at<float>(y, x) = static_cast<float>(uniform(rng, 0, 1));
  }
  if (cells == size) return grid;
  const int k = size / cells;
  const int pad = 2;
  cv::Mat padded;
  cv::copyMakeBorder(grid, padded, pad, pad, pad, pad, cv::BORDER_WRAP);
  cv::Mat up;
  cv::resize(padded, up, cv::Size((cells + 2 * pad) * k, (cells + 2 * pad) * k), 0, 0,
             cv::INTER_CUBIC);
  return up(cv::Rect(pad * k, pad * k, size, size)).clone();
}

/// Anisotropic variant: cells_x by cells_y grid (for wood grain and corrugation).
cv::Mat value_noise_aniso(Rng& rng, int size, int cells_x, int cells_y) {
  cells_x = std::clamp(cells_x, 1, size);
  cells_y = std::clamp(cells_y, 1, size);
  cv::Mat grid(cells_y, cells_x, CV_32FC1);
  for (int y = 0; y < cells_y; ++y) {
    for (int x = 0; x < cells_x; ++x) grid.at<float>(y, x) = static_cast<float>(uniform(rng, 0, 1));
  }
  const int kx = size / cells_x;
  const int ky = size / cells_y;
  const int pad = 2;
  cv::Mat padded;
  cv::copyMakeBorder(grid, padded, pad, pad, pad, pad, cv::BORDER_WRAP);
  cv::Mat up;
  cv::resize(padded, up, cv::Size((cells_x + 2 * pad) * kx, (cells_y + 2 * pad) * ky), 0, 0,
             cv::INTER_CUBIC);
  return up(cv::Rect(pad * kx, pad * ky, size, size)).clone();
}

cv::Mat normalized(const cv::Mat& m) {
  cv::Mat out;
  cv::normalize(m, out, 0.0, 1.0, cv::NORM_MINMAX);
  return out;
}

/// Maps a [0, 1] float image to 8 bits in [lo, hi].
cv::Mat to_u8(const cv::Mat& unit, double lo, double hi) {
  cv::Mat out;
  unit.convertTo(out, CV_8UC1, hi - lo, lo);
  return out;
}

/// Adds `amplitude` * (noise - 0.5) to an 8-bit image.
void add_noise(cv::Mat& img, const cv::Mat& unit_noise, double amplitude) {
  cv::Mat f;
  img.convertTo(f, CV_32FC1);
  f += (unit_noise - 0.5) * amplitude;
  f.convertTo(img, CV_8UC1);
}

std::string random_text(Rng& rng, int length) {
  static constexpr std::string_view kAlphabet = "ABCDEFGHJKLMNPRSTUVWXYZ0123456789-#";
  std::string s;
  for (int i = 0; i < length; ++i) {
    s.push_back(kAlphabet[static_cast<std::size_t>(
        uniform_int(rng, 0, static_cast<int>(kAlphabet.size()) - 1))]);
  }
  return s;
}

void draw_text(cv::Mat& img, const std::string& text, cv::Point org, double scale, int thickness,
               double value, int font = cv::FONT_HERSHEY_SIMPLEX) {
  draw_wrapped(img.cols, [&](cv::Point o) {
    cv::putText(img, text, org + o, font, scale, gray(value), thickness, cv::LINE_AA);
  });
}

void fill_rect(cv::Mat& img, cv::Rect r, double value) {
  draw_wrapped(img.cols, [&](cv::Point o) {
    cv::rectangle(img, r + o, gray(value), cv::FILLED, cv::LINE_8);
  });
}

void frame_rect(cv::Mat& img, cv::Rect r, double value, int thickness) {
  draw_wrapped(img.cols,
               [&](cv::Point o) { cv::rectangle(img, r + o, gray(value), thickness, cv::LINE_8); });
}

void fill_circle(cv::Mat& img, cv::Point c, int radius, double value) {
  draw_wrapped(img.cols, [&](cv::Point o) {
    cv::circle(img, c + o, radius, gray(value), cv::FILLED, cv::LINE_AA);
  });
}

void draw_line(cv::Mat& img, cv::Point a, cv::Point b, double value, int thickness) {
  draw_wrapped(img.cols, [&](cv::Point o) {
    cv::line(img, a + o, b + o, gray(value), thickness, cv::LINE_AA);
  });
}

cv::Point random_point(Rng& rng, int size) {
  return {uniform_int(rng, 0, size - 1), uniform_int(rng, 0, size - 1)};
}

/// Small dark and light dots: fine-scale corners.
void speckle(cv::Mat& img, Rng& rng, int count, int max_radius, double dark, double light) {
  for (int i = 0; i < count; ++i) {
    const cv::Point c = random_point(rng, img.cols);
    const int r = uniform_int(rng, 1, max_radius);
    fill_circle(img, c, r, uniform(rng, 0, 1) < 0.5 ? dark : light);
  }
}

/// Random-walk cracks of thickness 1.
void cracks(cv::Mat& img, Rng& rng, int count, int steps, double value) {
  for (int i = 0; i < count; ++i) {
    cv::Point p = random_point(rng, img.cols);
    double heading = uniform(rng, 0, 6.283185307179586);
    for (int k = 0; k < steps; ++k) {
      heading += uniform(rng, -0.7, 0.7);
      const double len = uniform(rng, 4, 14);
      const cv::Point q(p.x + static_cast<int>(std::lround(len * std::cos(heading))),
                        p.y + static_cast<int>(std::lround(len * std::sin(heading))));
      draw_line(img, p, q, value, 1);
      p = q;
    }
  }
}

/// A barcode: vertical bars of random widths inside `r`.
void barcode(cv::Mat& img, Rng& rng, cv::Rect r) {
  fill_rect(img, r, 235);
  int x = r.x + 3;
  while (x < r.x + r.width - 4) {
    const int w = uniform_int(rng, 1, 4);
    if (uniform(rng, 0, 1) < 0.55) fill_rect(img, cv::Rect(x, r.y + 3, w, r.height - 6), 20);
    x += w;
  }
}

/// Random filled shapes (rectangles, circles, triangles) of sizes in [min_size, max_size].
void shapes(cv::Mat& img, Rng& rng, int count, int min_size, int max_size, double lo, double hi) {
  for (int i = 0; i < count; ++i) {
    const cv::Point c = random_point(rng, img.cols);
    const int w = uniform_int(rng, min_size, max_size);
    const int h = uniform_int(rng, min_size, max_size);
    const double value = uniform(rng, lo, hi);
    switch (uniform_int(rng, 0, 2)) {
      case 0:
        fill_rect(img, cv::Rect(c.x, c.y, w, h), value);
        break;
      case 1:
        fill_circle(img, c, w / 2, value);
        break;
      default: {
        const std::array<cv::Point, 3> tri = {c, c + cv::Point(w, uniform_int(rng, 0, h)),
                                              c + cv::Point(uniform_int(rng, 0, w), h)};
        draw_wrapped(img.cols, [&](cv::Point o) {
          std::array<cv::Point, 3> moved = {tri[0] + o, tri[1] + o, tri[2] + o};
          cv::fillConvexPoly(img, moved.data(), 3, gray(value), cv::LINE_AA);
        });
      }
    }
  }
}

cv::Mat concrete(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 7, 0.62), 85, 185);
  const cv::Mat stain = fbm_noise(rng, s, 2, 5, 0.5);
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) {
      const float a = stain.at<float>(y, x);
      if (a > 0.62f) {
        img.at<std::uint8_t>(y, x) =
            cv::saturate_cast<std::uint8_t>(img.at<std::uint8_t>(y, x) - (a - 0.62f) * 160.0f);
      }
    }
  }
  speckle(img, rng, s * s / 160, 2, 55, 215);
  cracks(img, rng, 5, 14, 45);
  // Slab joints along the tile border and one across the middle.
  draw_line(img, {0, 0}, {s, 0}, 50, 2);
  draw_line(img, {0, 0}, {0, s}, 50, 2);
  draw_line(img, {s / 2, 0}, {s / 2, s}, 70, 1);
  return img;
}

cv::Mat bricks(Rng& rng, int s) {
  const int rows = 16;
  const int row_h = s / rows;
  const int brick_w = 2 * row_h;
  const int mortar = std::max(2, row_h / 8);
  cv::Mat img(s, s, CV_8UC1, gray(uniform(rng, 170, 205)));
  for (int r = 0; r < rows; ++r) {
    const int shift = (r % 2) * brick_w / 2;
    for (int x = -brick_w; x < s; x += brick_w) {
      const double value = uniform(rng, 60, 150);
      fill_rect(img,
                cv::Rect(x + shift + mortar / 2, r * row_h + mortar / 2, brick_w - mortar,
                         row_h - mortar),
                value);
    }
  }
  add_noise(img, fbm_noise(rng, s, 8, 6, 0.7), 70);
  speckle(img, rng, s * s / 400, 2, 40, 200);
  return img;
}

cv::Mat metal_panels(Rng& rng, int s) {
  cv::Mat img(s, s, CV_8UC1);
  const double base = uniform(rng, 110, 160);
  const int period = s / 32;
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) {
      // Trapezoidal corrugation profile: flat crests, sloped flanks (shaded darker).
      const int phase = x % period;
      const double shade = phase < period / 4 ? 25 : (phase < period / 2 ? -20 : 5);
      img.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(base + shade);
    }
  }
  add_noise(img, fbm_noise(rng, s, 4, 6, 0.6), 60);
  // Panel seams and rivet rows.
  for (int y = 0; y < s; y += s / 2) {
    draw_line(img, {0, y}, {s, y}, 40, 3);
    for (int x = period / 2; x < s; x += period) fill_circle(img, {x, y + 8}, 2, 30);
  }
  draw_line(img, {0, 0}, {0, s}, 45, 3);
  // Stickers and signs.
  for (int i = 0; i < 3; ++i) {
    const cv::Point c = random_point(rng, s);
    const int w = uniform_int(rng, s / 10, s / 4);
    const int h = uniform_int(rng, s / 16, s / 8);
    fill_rect(img, cv::Rect(c.x, c.y, w, h), uniform(rng, 0, 1) < 0.5 ? 230 : 35);
    const double ink = img.at<std::uint8_t>(c.y % s, c.x % s) > 128 ? 20 : 230;
    draw_text(img, random_text(rng, uniform_int(rng, 3, 6)), {c.x + 4, c.y + h * 2 / 3}, h / 40.0,
              2, ink);
  }
  speckle(img, rng, s * s / 600, 2, 40, 210);
  return img;
}

cv::Mat ceiling(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 8, 5, 0.55), 150, 190);
  const int panel = s / 8;
  for (int i = 0; i <= 8; ++i) {
    draw_line(img, {i * panel, 0}, {i * panel, s}, 90, 3);
    draw_line(img, {0, i * panel}, {s, i * panel}, 90, 3);
  }
  // Light fixtures: bright two-panel rectangles with a dark frame; vents: slotted squares.
  for (int i = 0; i < 6; ++i) {
    const int px = uniform_int(rng, 0, 7) * panel;
    const int py = uniform_int(rng, 0, 6) * panel;
    if (uniform(rng, 0, 1) < 0.6) {
      fill_rect(img, cv::Rect(px + 6, py + 6, panel - 12, 2 * panel - 12), 250);
      frame_rect(img, cv::Rect(px + 6, py + 6, panel - 12, 2 * panel - 12), 60, 2);
    } else {
      fill_rect(img, cv::Rect(px + 10, py + 10, panel - 20, panel - 20), 120);
      for (int y = py + 14; y < py + panel - 14; y += 6) {
        draw_line(img, {px + 14, y}, {px + panel - 14, y}, 40, 2);
      }
    }
  }
  speckle(img, rng, s * s / 900, 2, 80, 220);
  return img;
}

cv::Mat cardboard(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 6, 0.55), 115, 165);
  // Tape band and printed markings.
  const int tape_y = s / 2 - s / 16;
  fill_rect(img, cv::Rect(0, tape_y, s, s / 8), uniform(rng, 175, 205));
  draw_line(img, {0, tape_y}, {s, tape_y}, 95, 1);
  // Label with text lines and a barcode.
  const cv::Rect label(uniform_int(rng, s / 16, s / 2), uniform_int(rng, s / 16, s / 8), s / 3,
                       s / 4);
  fill_rect(img, label, 232);
  for (int l = 0; l < 3; ++l) {
    draw_text(img, random_text(rng, 7), {label.x + 6, label.y + 22 + l * 24}, 0.6, 2, 25);
  }
  barcode(img, rng, cv::Rect(label.x + 6, label.y + label.height - 46, label.width - 12, 40));
  // Large stencilled code and arrows.
  draw_text(img, random_text(rng, 4), {s / 10, s * 7 / 8}, 2.2, 5, 45, cv::FONT_HERSHEY_DUPLEX);
  for (int i = 0; i < 2; ++i) {
    const cv::Point a(uniform_int(rng, s / 2, s - 60), uniform_int(rng, s * 5 / 8, s - 40));
    draw_wrapped(s, [&](cv::Point o) {
      cv::arrowedLine(img, a + o, a + o + cv::Point(0, -50), gray(40), 5, cv::LINE_AA, 0, 0.35);
    });
  }
  speckle(img, rng, s * s / 1200, 2, 70, 200);
  return img;
}

cv::Mat poster(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 2, 4, 0.5), uniform(rng, 60, 120), uniform(rng, 150, 230));
  shapes(img, rng, uniform_int(rng, 8, 16), s / 12, s / 3, 10, 245);
  shapes(img, rng, 40, s / 64, s / 20, 10, 245);
  const double ink = uniform(rng, 0, 1) < 0.5 ? 15 : 240;
  draw_text(img, random_text(rng, uniform_int(rng, 4, 7)), {s / 16, s / 4}, s / 180.0, 6, ink,
            cv::FONT_HERSHEY_DUPLEX);
  for (int l = 0; l < 6; ++l) {
    draw_text(img, random_text(rng, uniform_int(rng, 10, 16)), {s / 16, s / 2 + l * s / 14},
              s / 700.0, 2, ink);
  }
  frame_rect(img, cv::Rect(0, 0, s, s), 25, 6);
  return img;
}

cv::Mat shelf_upright(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 5, 0.5), 85, 125);
  // Punched holes: two columns of rectangular slots, every 1/16 of the tile.
  const int step = s / 16;
  for (int y = 0; y < s; y += step) {
    for (const int x : {s / 4, 3 * s / 4 - s / 16}) {
      fill_rect(img, cv::Rect(x, y + step / 4, s / 16, step / 2), 15);
    }
    fill_circle(img, {s / 2, y + step / 2}, s / 48, 25);
  }
  draw_line(img, {s / 8, 0}, {s / 8, s}, 170, 3);  // bend highlight
  speckle(img, rng, s * s / 1500, 2, 40, 190);
  return img;
}

cv::Mat shelf_beam(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 5, 0.5), 95, 135);
  draw_line(img, {0, s / 10}, {s, s / 10}, 175, 4);
  draw_line(img, {0, s - s / 10}, {s, s - s / 10}, 55, 4);
  for (int i = 0; i < 2; ++i) {
    const cv::Rect label(i * s / 2 + uniform_int(rng, 10, s / 8), s / 4, s / 4, s / 2);
    fill_rect(img, label, 235);
    draw_text(img, random_text(rng, 4), {label.x + 6, label.y + label.height / 2}, s / 400.0, 3,
              20);
    barcode(
        img, rng,
        cv::Rect(label.x + 4, label.y + label.height * 3 / 5, label.width - 8, label.height / 3));
  }
  speckle(img, rng, s * s / 1500, 2, 40, 190);
  return img;
}

cv::Mat wood(Rng& rng, int s) {
  const cv::Mat grain = normalized(value_noise_aniso(rng, s, 4, 64) * 0.6f +
                                   value_noise_aniso(rng, s, 16, 128) * 0.4f);
  cv::Mat img = to_u8(grain, 110, 190);
  const int plank = s / 6;
  for (int i = 0; i < 6; ++i) {
    const double shade = uniform(rng, -25, 25);
    cv::Mat band = img(cv::Rect(0, i * plank, s, plank));
    band.convertTo(band, CV_8UC1, 1.0, shade);
    draw_line(img, {0, i * plank}, {s, i * plank}, 30, 5);
    for (int k = 0; k < 2; ++k) {
      const cv::Point c(uniform_int(rng, 0, s - 1), i * plank + uniform_int(rng, 15, plank - 15));
      const cv::Size axes(uniform_int(rng, 6, 14), 5);
      draw_wrapped(s, [&](cv::Point o) {
        cv::ellipse(img, c + o, axes, 0, 0, 360, gray(60), cv::FILLED, cv::LINE_AA);
      });
    }
    fill_circle(img, {s / 8, i * plank + plank / 2}, 5, 35);  // nails
    fill_circle(img, {s * 5 / 8, i * plank + plank / 2}, 5, 35);
  }
  return img;
}

cv::Mat clutter(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 7, 0.65), 70, 180);
  shapes(img, rng, 12, s / 10, s / 4, 20, 235);
  shapes(img, rng, 60, s / 40, s / 12, 20, 235);
  shapes(img, rng, 200, 3, s / 50, 20, 235);
  for (int i = 0; i < 4; ++i) {
    draw_text(img, random_text(rng, 5), random_point(rng, s), uniform(rng, 0.6, 1.6), 2,
              uniform(rng, 0, 1) < 0.5 ? 20 : 235);
  }
  return img;
}

cv::Mat asphalt(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 7, 0.7), 55, 125);
  shapes(img, rng, 6, s / 8, s / 3, 45, 95);  // patches
  // Fine grain of low contrast (real asphalt gives few strong corners), a few cracks.
  add_noise(img, fbm_noise(rng, s, 64, 3, 0.8), 40);
  speckle(img, rng, s * s / 300, 1, 60, 120);
  cracks(img, rng, 6, 18, 35);
  return img;
}

cv::Mat paint(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 6, 0.6), 175, 235);
  speckle(img, rng, s * s / 1500, 3, 150, 240);  // wear
  return img;
}

cv::Mat pavers(Rng& rng, int s) {
  cv::Mat img(s, s, CV_8UC1);
  const int tile = s / 8;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      img(cv::Rect(x * tile, y * tile, tile, tile)).setTo(gray(uniform(rng, 110, 175)));
    }
  }
  add_noise(img, fbm_noise(rng, s, 16, 5, 0.6), 50);
  for (int i = 0; i <= 8; ++i) {
    draw_line(img, {i * tile, 0}, {i * tile, s}, 55, 3);
    draw_line(img, {0, i * tile}, {s, i * tile}, 55, 3);
  }
  speckle(img, rng, s * s / 500, 2, 50, 210);
  return img;
}

/// A window of the facade: frame, glass with reflections, mullions, sill; sometimes blinds.
void window(cv::Mat& img, Rng& rng, cv::Rect r, const cv::Mat& reflections) {
  fill_rect(img, r, 205);
  const cv::Rect glass(r.x + 6, r.y + 6, r.width - 12, r.height - 12);
  cv::Mat g = img(glass);
  cv::Mat refl = reflections(cv::Rect(glass.x % 64, glass.y % 64, glass.width, glass.height));
  refl.convertTo(g, CV_8UC1, uniform(rng, 60, 120), uniform(rng, 20, 50));
  if (uniform(rng, 0, 1) < 0.3) {
    for (int y = glass.y; y < glass.y + glass.height / 2; y += 5) {
      draw_line(img, {glass.x, y}, {glass.x + glass.width, y}, 185, 2);
    }
  }
  draw_line(img, {r.x + r.width / 2, r.y}, {r.x + r.width / 2, r.y + r.height}, 200, 4);
  draw_line(img, {r.x, r.y + r.height / 3}, {r.x + r.width, r.y + r.height / 3}, 200, 4);
  fill_rect(img, cv::Rect(r.x - 6, r.y + r.height, r.width + 12, 8), 225);
}

cv::Mat facade(Rng& rng, int s) {
  cv::Mat img;
  if (uniform(rng, 0, 1) < 0.4) {
    img = bricks(rng, s);
  } else {
    img = to_u8(fbm_noise(rng, s, 4, 7, 0.6), uniform(rng, 80, 140), uniform(rng, 170, 220));
  }
  const cv::Mat reflections = fbm_noise(rng, s, 4, 5, 0.6);
  // Module: 2 floors x 3 windows.
  const int floor_h = s / 2;
  const int bay_w = s / 3;
  for (int f = 0; f < 2; ++f) {
    fill_rect(img, cv::Rect(0, f * floor_h + 3, s, 6), 95);  // floor cornice
    for (int b = 0; b < 3; ++b) {
      const cv::Rect r(b * bay_w + bay_w / 5, f * floor_h + floor_h / 5, bay_w * 3 / 5,
                       floor_h * 3 / 5);
      window(img, rng, r, reflections);
    }
  }
  speckle(img, rng, s * s / 900, 2, 40, 220);
  return img;
}

cv::Mat shop_front(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 6, 0.6), 60, 120);
  const cv::Mat reflections = fbm_noise(rng, s, 4, 5, 0.6);
  // Sign band with the shop name, then a large window with posters behind the glass.
  const cv::Rect sign(0, s / 16, s, s / 5);
  fill_rect(img, sign, uniform(rng, 0, 1) < 0.5 ? 225 : 30);
  const double ink = img.at<std::uint8_t>(sign.y + 2, 2) > 128 ? 20 : 235;
  draw_text(img, random_text(rng, uniform_int(rng, 4, 8)), {s / 20, sign.y + sign.height * 3 / 4},
            s / 200.0, 6, ink, cv::FONT_HERSHEY_DUPLEX);
  const cv::Rect glass(s / 16, s / 3, s * 7 / 8, s / 2);
  window(img, rng, glass, reflections);
  for (int i = 0; i < 3; ++i) {
    const cv::Rect p(glass.x + 20 + i * glass.width / 3, glass.y + glass.height / 2,
                     glass.width / 5, glass.height / 3);
    fill_rect(img, p, uniform(rng, 150, 240));
    draw_text(img, random_text(rng, 3), {p.x + 4, p.y + p.height / 2}, 0.9, 2, 25);
  }
  return img;
}

cv::Mat car_side(Rng& rng, int s) {
  const double paint_value = uniform(rng, 35, 220);
  cv::Mat img = to_u8(fbm_noise(rng, s, 2, 4, 0.5), paint_value - 12, paint_value + 12);
  const double seam = paint_value > 110 ? paint_value - 70 : paint_value + 60;
  // Doors, handles, trim.
  for (const int x : {s * 3 / 10, s * 11 / 20, s * 4 / 5}) {
    draw_line(img, {x, s / 10}, {x - 10, s * 7 / 10}, seam, 2);
  }
  fill_rect(img, cv::Rect(s * 3 / 10 + 20, s / 4, 40, 10), seam);
  fill_rect(img, cv::Rect(s * 11 / 20 + 20, s / 4, 40, 10), seam);
  draw_line(img, {0, s / 2}, {s, s / 2}, seam, 3);
  // Wheels: tyres, rims with spokes.
  for (const int x : {s / 5, s * 4 / 5}) {
    const cv::Point c(x, s * 13 / 16);
    fill_circle(img, c, s / 6, 25);
    fill_circle(img, c, s / 10, 170);
    for (int k = 0; k < 5; ++k) {
      const double a = k * 1.2566370614359172;
      draw_line(img, c,
                c + cv::Point(static_cast<int>(s / 10 * std::cos(a)),
                              static_cast<int>(s / 10 * std::sin(a))),
                70, 4);
    }
    fill_circle(img, c, s / 40, 60);
  }
  return img;
}

cv::Mat car_end(Rng& rng, int s) {
  const double paint_value = uniform(rng, 35, 220);
  cv::Mat img = to_u8(fbm_noise(rng, s, 2, 4, 0.5), paint_value - 10, paint_value + 10);
  // Lights, grille, plate with text, bumper.
  fill_rect(img, cv::Rect(s / 16, s / 5, s / 4, s / 6), 240);
  fill_rect(img, cv::Rect(s * 11 / 16, s / 5, s / 4, s / 6), 240);
  fill_rect(img, cv::Rect(s * 3 / 8, s / 5, s / 4, s / 5), 30);
  for (int y = s / 5 + 6; y < s * 2 / 5; y += 8) {
    draw_line(img, {s * 3 / 8, y}, {s * 5 / 8, y}, 120, 2);
  }
  const cv::Rect plate(s * 5 / 16, s / 2, s * 3 / 8, s / 8);
  fill_rect(img, plate, 235);
  frame_rect(img, plate, 20, 2);
  draw_text(img, random_text(rng, 6), {plate.x + 6, plate.y + plate.height * 3 / 4}, s / 600.0, 2,
            15);
  fill_rect(img, cv::Rect(0, s * 3 / 4, s, s / 8), 45);
  return img;
}

cv::Mat car_glass(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 4, 5, 0.6), 25, 95);
  const double pillar = uniform(rng, 30, 200);
  for (const int x : {0, s / 2 - 8, s - 16}) {
    fill_rect(img, cv::Rect(x, 0, 16, s), pillar);
  }
  fill_rect(img, cv::Rect(0, 0, s, 14), pillar);
  fill_rect(img, cv::Rect(0, s - 14, s, 14), pillar);
  // Reflections of the sky: bright slanted streaks.
  for (int i = 0; i < 3; ++i) {
    const int x = uniform_int(rng, 0, s - 1);
    draw_line(img, {x, 0}, {x + s / 4, s}, 170, uniform_int(rng, 6, 20));
  }
  return img;
}

cv::Mat foliage(Rng& rng, int s) {
  cv::Mat img = to_u8(fbm_noise(rng, s, 8, 5, 0.6), 30, 80);
  for (int i = 0; i < s * s / 150; ++i) {
    const cv::Point c = random_point(rng, s);
    const int r = uniform_int(rng, 2, s / 40);
    fill_circle(img, c, r, uniform(rng, 25, 170));
  }
  return img;
}

cv::Mat bark(Rng& rng, int s) {
  const cv::Mat streaks = normalized(value_noise_aniso(rng, s, 32, 4) * 0.7f +
                                     value_noise_aniso(rng, s, 128, 16) * 0.3f);
  cv::Mat img = to_u8(streaks, 40, 150);
  speckle(img, rng, s * s / 800, 3, 25, 160);
  return img;
}

cv::Mat clouds(Rng& rng, int s) {
  cv::Mat c = fbm_noise(rng, s, 4, 6, 0.55);
  cv::Mat img(s, s, CV_8UC1);
  for (int y = 0; y < s; ++y) {
    for (int x = 0; x < s; ++x) {
      // Clear sky below a threshold, then increasingly bright and textured clouds.
      const float a = std::clamp((c.at<float>(y, x) - 0.45f) * 3.0f, 0.0f, 1.0f);
      img.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(170.0f + 80.0f * a);
    }
  }
  return img;
}

}  // namespace

std::string_view to_string(TextureKind kind) {
  switch (kind) {
    case TextureKind::kConcrete:
      return "concrete";
    case TextureKind::kBricks:
      return "bricks";
    case TextureKind::kMetalPanels:
      return "metal_panels";
    case TextureKind::kCeiling:
      return "ceiling";
    case TextureKind::kCardboard:
      return "cardboard";
    case TextureKind::kPoster:
      return "poster";
    case TextureKind::kShelfUpright:
      return "shelf_upright";
    case TextureKind::kShelfBeam:
      return "shelf_beam";
    case TextureKind::kWood:
      return "wood";
    case TextureKind::kClutter:
      return "clutter";
    case TextureKind::kAsphalt:
      return "asphalt";
    case TextureKind::kPaint:
      return "paint";
    case TextureKind::kPavers:
      return "pavers";
    case TextureKind::kFacade:
      return "facade";
    case TextureKind::kShopFront:
      return "shop_front";
    case TextureKind::kCarSide:
      return "car_side";
    case TextureKind::kCarEnd:
      return "car_end";
    case TextureKind::kCarGlass:
      return "car_glass";
    case TextureKind::kFoliage:
      return "foliage";
    case TextureKind::kBark:
      return "bark";
    case TextureKind::kClouds:
      return "clouds";
  }
  return "unknown";
}

cv::Mat fbm_noise(Rng& rng, int size, int base_cells, int octaves, double persistence) {
  cv::Mat sum = cv::Mat::zeros(size, size, CV_32FC1);
  double amplitude = 1.0;
  int cells = base_cells;
  for (int o = 0; o < octaves && cells <= size; ++o) {
    sum += value_noise(rng, size, cells) * amplitude;
    amplitude *= persistence;
    cells *= 2;
  }
  return normalized(sum);
}

cv::Mat make_texture_image(TextureKind kind, std::uint64_t seed, int size) {
  if (size < 64 || (size & (size - 1)) != 0) {
    throw std::runtime_error("synthetic texture: size must be a power of two >= 64, got " +
                             std::to_string(size));
  }
  Rng rng(seed);
  switch (kind) {
    case TextureKind::kConcrete:
      return concrete(rng, size);
    case TextureKind::kBricks:
      return bricks(rng, size);
    case TextureKind::kMetalPanels:
      return metal_panels(rng, size);
    case TextureKind::kCeiling:
      return ceiling(rng, size);
    case TextureKind::kCardboard:
      return cardboard(rng, size);
    case TextureKind::kPoster:
      return poster(rng, size);
    case TextureKind::kShelfUpright:
      return shelf_upright(rng, size);
    case TextureKind::kShelfBeam:
      return shelf_beam(rng, size);
    case TextureKind::kWood:
      return wood(rng, size);
    case TextureKind::kClutter:
      return clutter(rng, size);
    case TextureKind::kAsphalt:
      return asphalt(rng, size);
    case TextureKind::kPaint:
      return paint(rng, size);
    case TextureKind::kPavers:
      return pavers(rng, size);
    case TextureKind::kFacade:
      return facade(rng, size);
    case TextureKind::kShopFront:
      return shop_front(rng, size);
    case TextureKind::kCarSide:
      return car_side(rng, size);
    case TextureKind::kCarEnd:
      return car_end(rng, size);
    case TextureKind::kCarGlass:
      return car_glass(rng, size);
    case TextureKind::kFoliage:
      return foliage(rng, size);
    case TextureKind::kBark:
      return bark(rng, size);
    case TextureKind::kClouds:
      return clouds(rng, size);
  }
  throw std::runtime_error("synthetic texture: unknown kind");
}

}  // namespace edx::synthetic

#include "atmosphere/tools/reference_renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include "atmosphere/model_spectrum.h"
#include "engine/core/luminance.h"
#include "engine/core/math_constants.h"
#include "engine/shading/phase_functions.h"

namespace cr {

namespace {

struct Rng {
  uint64_t state;
  uint64_t next_u64() {  // splitmix64
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next_u64() >> 11) * (1.0 / 9007199254740992.0); }
};

struct Medium {
  glm::dvec3 rayleigh;
  glm::dvec3 mie;
  glm::dvec3 scattering;
  glm::dvec3 extinction;
};

class Reference {
 public:
  explicit Reference(const AtmosphereModel& m) : m_(m), R_(m.bottom_radius), top_(m.top_radius) {}

  Medium medium(double h) const {
    h = std::max(h, 0.0);
    const double dr = std::exp(-h / m_.rayleigh_scale_height);
    const double dm = std::exp(-h / m_.mie_scale_height);
    const double dz = std::max(0.0, 1.0 - std::abs(h - m_.ozone_center) / m_.ozone_half_width);
    Medium s;
    s.rayleigh = glm::dvec3(m_.rayleigh_scattering) * dr;
    s.mie = glm::dvec3(m_.mie_scattering) * dm;
    s.scattering = s.rayleigh + s.mie;
    s.extinction = s.scattering + glm::dvec3(m_.mie_absorption) * dm + glm::dvec3(m_.ozone_absorption) * dz;
    return s;
  }
  double altitude(const glm::dvec3& p) const { return glm::length(p) - R_; }
  // Altitude-adaptive step: ~300 m near the ground (a quarter of the Mie scale height), up to 10 km.
  static double step(double h) { return std::clamp(300.0 + 0.1 * h, 300.0, 10000.0); }

  struct Span {
    bool valid = false;
    bool ground = false;
    double t0 = 0.0, t1 = 0.0;
  };
  Span span(const glm::dvec3& o, const glm::dvec3& d) const {
    Span s;
    const double b = glm::dot(o, d);
    const double c_top = glm::dot(o, o) - top_ * top_;
    const double disc_top = b * b - c_top;
    if (disc_top < 0.0) return s;
    const double sq = std::sqrt(disc_top);
    if (c_top > 0.0) {  // outside: enter if heading in
      if (b >= 0.0) return s;
      s.t0 = -b - sq;
    }
    s.t1 = -b + sq;
    const double c_ground = glm::dot(o, o) - R_ * R_;
    const double disc_g = b * b - c_ground;
    if (b < 0.0 && disc_g >= 0.0) {
      const double tg = -b - std::sqrt(disc_g);
      if (tg >= s.t0) {
        s.t1 = tg;
        s.ground = true;
      }
    }
    s.valid = s.t1 > s.t0;
    return s;
  }

  glm::dvec3 optical_depth(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1) const {
    glm::dvec3 tau(0.0);
    double t = t0;
    while (t < t1) {
      const double ds = std::min(step(altitude(o + t * d)), t1 - t);
      tau += medium(altitude(o + (t + 0.5 * ds) * d)).extinction * ds;
      t += ds;
    }
    return tau;
  }

  glm::dvec3 to_top(const glm::dvec3& x, const glm::dvec3& dir) const {
    const Span s = span(x, dir);
    if (s.ground) return glm::dvec3(0.0);
    if (!s.valid) return glm::dvec3(1.0);
    return glm::exp(-optical_depth(x, dir, s.t0, s.t1));
  }

  // Relative densities (1 at the ground; ozone: at the tent's peak), the same for every wavelength.
  glm::dvec3 densities(double h) const {
    h = std::max(h, 0.0);
    return {std::exp(-h / m_.rayleigh_scale_height), std::exp(-h / m_.mie_scale_height),
            std::max(0.0, 1.0 - std::abs(h - m_.ozone_center) / m_.ozone_half_width)};
  }
  // Column densities (Rayleigh, Mie, ozone; m) along [t0, t1], by the same steps as optical_depth.
  glm::dvec3 column(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1) const {
    glm::dvec3 col(0.0);
    double t = t0;
    while (t < t1) {
      const double ds = std::min(step(altitude(o + t * d)), t1 - t);
      col += densities(altitude(o + (t + 0.5 * ds) * d)) * ds;
      t += ds;
    }
    return col;
  }

  // The ray towards the sun from x: the visible fraction of the sun disk (the
  // same smooth shadow edge as the LUT method) and the span it crosses.
  struct SunRay {
    double visible = 0.0;
    glm::dvec3 dir{0.0};
    Span span;
  };
  SunRay sun_ray(const glm::dvec3& x, const glm::dvec3& s) const {
    SunRay ray;
    const double r = glm::length(x);
    const glm::dvec3 up = x / r;
    const double mu = glm::dot(up, s);
    const double mu_h = -std::sqrt(std::max(0.0, 1.0 - (R_ / r) * (R_ / r)));
    const double pen = std::sin(double(m_.sun_angular_radius)) * (R_ / r);
    const double above = mu - mu_h;
    if (above <= -pen) return ray;
    ray.visible = 1.0;
    ray.dir = s;
    if (above < pen) {
      const double f = (above + pen) / (2.0 * pen);
      ray.visible = f * f * (3.0 - 2.0 * f);
      if (mu < mu_h + 1e-9) {  // the disk centre is below the horizon: use the grazing ray
        glm::dvec3 hz = s - mu * up;
        const double len = glm::length(hz);
        hz = len > 0.0 ? hz / len : glm::dvec3(1.0, 0.0, 0.0);
        ray.dir = (mu_h + 1e-9) * up + std::sqrt(std::max(0.0, 1.0 - (mu_h + 1e-9) * (mu_h + 1e-9))) * hz;
      }
    }
    ray.span = span(x, ray.dir);
    return ray;
  }

  // Sunlight reaching x: transmittance times the visible fraction of the sun disk.
  glm::dvec3 sun(const glm::dvec3& x, const glm::dvec3& s) const {
    const SunRay ray = sun_ray(x, s);
    if (ray.visible <= 0.0) return glm::dvec3(0.0);
    if (!ray.span.valid) return glm::dvec3(ray.visible);
    return ray.visible * glm::exp(-optical_depth(x, ray.dir, ray.span.t0, ray.span.t1));
  }

  double phase_mie(double c) const {
    if (m_.mie_phase == MiePhaseModel::CornetteShanks) return cornette_shanks<double>(c, m_.mie_g);
    return m_.mie_lobe_weight * hg(c, m_.mie_g) + (1.0 - m_.mie_lobe_weight) * hg(c, m_.mie_g2);
  }
  static double hg(double c, double g) { return henyey_greenstein(c, g); }

  // Mie sampling proxy: the HG lobe(s); pdf of cos around the travel direction.
  double mie_proxy_pdf(double c) const {
    if (m_.mie_phase == MiePhaseModel::CornetteShanks) return hg(c, m_.mie_g);
    return m_.mie_lobe_weight * hg(c, m_.mie_g) + (1.0 - m_.mie_lobe_weight) * hg(c, m_.mie_g2);
  }
  double sample_mie_cos(Rng& rng) const {
    double g = m_.mie_g;
    if (m_.mie_phase == MiePhaseModel::DoubleHenyeyGreenstein && rng.uniform() >= m_.mie_lobe_weight) g = m_.mie_g2;
    const double u = rng.uniform();
    if (std::abs(g) < 1e-4) return 1.0 - 2.0 * u;
    const double q = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    return std::clamp((1.0 + g * g - q * q) / (2.0 * g), -1.0, 1.0);
  }

  const AtmosphereModel& m_;
  double R_, top_;
};

glm::dvec3 around(const glm::dvec3& axis, double cos_t, double phi) {
  const glm::dvec3 ref = std::abs(axis.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(axis, ref));
  const glm::dvec3 v = glm::cross(axis, u);
  const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
  return glm::normalize(axis * cos_t + (u * std::cos(phi) + v * std::sin(phi)) * sin_t);
}

double mean(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }
double max_component(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

// One group's coefficients (/m at the ground or the ozone peak), per channel.
struct GroupCoefficients {
  glm::dvec3 rayleigh, mie, mie_extinction, ozone, albedo;
  explicit GroupCoefficients(const AtmosphereModel& m)
      : rayleigh(m.rayleigh_scattering),
        mie(m.mie_scattering),
        mie_extinction(glm::dvec3(m.mie_scattering) + glm::dvec3(m.mie_absorption)),
        ozone(m.ozone_absorption),
        albedo(m.ground_albedo) {}
  // Extinction (or optical depth) from densities (or column densities).
  glm::dvec3 extinction(const glm::dvec3& dens) const {
    return rayleigh * dens.x + mie_extinction * dens.y + ozone * dens.z;
  }
};

// Sunlight reaching a point, per group: the visible fraction of the disk times
// each group's transmittance through the column.
struct SunColumn {
  double visible = 0.0;
  glm::dvec3 column{0.0};
  glm::dvec3 at(const GroupCoefficients& k) const {
    return visible > 0.0 ? visible * glm::exp(-k.extinction(column)) : glm::dvec3(0.0);
  }
};

SunColumn sun_column(const Reference& ref, const glm::dvec3& x, const glm::dvec3& s) {
  SunColumn c;
  const Reference::SunRay ray = ref.sun_ray(x, s);
  c.visible = ray.visible;
  if (ray.visible > 0.0 && ray.span.valid) c.column = ref.column(x, ray.dir, ray.span.t0, ray.span.t1);
  return c;
}

// Single scattering plus the directly seen sunlit ground, deterministic, for a
// unit sun in every channel of every group (`l`: one value per group). The
// geometry (the view march and each step's nested sun march) is done once:
// column densities, turned into each group's optical depths.
void single_scattering(const Reference& ref, const std::vector<GroupCoefficients>& groups, const glm::dvec3& o,
                       const glm::dvec3& d, const glm::dvec3& s, std::vector<glm::dvec3>& l) {
  const size_t g_count = groups.size();
  l.assign(g_count, glm::dvec3(0.0));
  const Reference::Span sp = ref.span(o, d);
  if (!sp.valid) return;
  const double nu = glm::dot(d, s);
  const double pr = rayleigh_phase(nu), pm = ref.phase_mie(nu);
  std::vector<glm::dvec3> throughput(g_count, glm::dvec3(1.0));
  double t = sp.t0;
  while (t < sp.t1) {
    const double ds = std::min(Reference::step(ref.altitude(o + t * d)), sp.t1 - t);
    const glm::dvec3 x = o + (t + 0.5 * ds) * d;
    const glm::dvec3 dens = ref.densities(ref.altitude(x));
    const SunColumn sun = sun_column(ref, x, s);
    for (size_t g = 0; g < g_count; ++g) {
      const GroupCoefficients& k = groups[g];
      const glm::dvec3 extinction = k.extinction(dens);
      const glm::dvec3 source = (k.rayleigh * dens.x * pr + k.mie * dens.y * pm) * sun.at(k);
      glm::dvec3 seg;
      for (int c = 0; c < 3; ++c)
        seg[c] = extinction[c] > 0.0 ? -std::expm1(-extinction[c] * ds) / extinction[c] : ds;
      l[g] += throughput[g] * source * seg;
      throughput[g] *= glm::exp(-extinction * ds);
    }
    t += ds;
  }
  if (sp.ground) {
    const glm::dvec3 xg = o + sp.t1 * d;
    const glm::dvec3 n = glm::normalize(xg);
    const SunColumn sun = sun_column(ref, xg, s);
    const double cos_sun = std::max(0.0, glm::dot(n, s));
    for (size_t g = 0; g < g_count; ++g)
      l[g] += throughput[g] * groups[g].albedo / kPiD * sun.at(groups[g]) * cos_sun;
  }
}

// Continues a path leaving `pos` along `dir` with `throughput`; `vertex` is the
// index of the next vertex. Returns the sun light it gathers at vertices >= 2.
glm::dvec3 trace(const Reference& ref, glm::dvec3 pos, glm::dvec3 dir, glm::dvec3 throughput, int first_vertex,
                 const glm::dvec3& s, const glm::dvec3& e, int max_bounces, Rng& rng);

// Scatters at a volume vertex: picks the next direction and updates the throughput.
void scatter(const Reference& ref, const Medium& at, glm::dvec3& dir, glm::dvec3& throughput, Rng& rng) {
  const double a = mean(at.rayleigh) / std::max(mean(at.scattering), 1e-300);
  double c;
  if (rng.uniform() < a) {
    c = 1.0 - 2.0 * rng.uniform();
  } else {
    c = ref.sample_mie_cos(rng);
  }
  const double q = a / (4.0 * kPiD) + (1.0 - a) * ref.mie_proxy_pdf(c);
  const glm::dvec3 f = at.rayleigh * rayleigh_phase(c) + at.mie * ref.phase_mie(c);
  throughput = throughput * f / q;
  dir = around(dir, c, 2.0 * kPiD * rng.uniform());
}

// One path's estimate of orders >= 2 (the first vertex's sun term is single
// scattering). The first vertex is split: a volume collision forced inside the
// segment (distance sampled from the truncated free-flight pdf, spectral MIS)
// plus, when the ray hits the ground, the ground vertex weighted by the
// transmittance; so no path is wasted on rays that would leave the atmosphere.
// Free flight along a span: marches until the optical depth of `channel`
// reaches `target` (a collision) or the span ends, with exact interpolation
// inside the step where it crosses.
struct FreeFlight {
  double t = 0.0;
  glm::dvec3 tau{0.0};
  Medium medium{};
  bool collided = false;
};

FreeFlight fly(const Reference& ref, const glm::dvec3& pos, const glm::dvec3& dir, const Reference::Span& sp,
               int channel, double target) {
  FreeFlight f;
  f.t = sp.t0;
  while (f.t < sp.t1) {
    const double ds = std::min(Reference::step(ref.altitude(pos + f.t * dir)), sp.t1 - f.t);
    const Medium med = ref.medium(ref.altitude(pos + (f.t + 0.5 * ds) * dir));
    const glm::dvec3 next = f.tau + med.extinction * ds;
    if (next[channel] >= target && med.extinction[channel] > 0.0) {
      const double dt = (target - f.tau[channel]) / med.extinction[channel];
      f.t += dt;
      f.tau += med.extinction * dt;
      f.medium = med;
      f.collided = true;
      return f;
    }
    f.tau = next;
    f.t += ds;
  }
  return f;
}

glm::dvec3 multiple_scattering_path(const Reference& ref, glm::dvec3 pos, glm::dvec3 dir, const glm::dvec3& s,
                                    const glm::dvec3& e, int max_bounces, Rng& rng) {
  const Reference::Span sp = ref.span(pos, dir);
  if (!sp.valid) return glm::dvec3(0.0);
  glm::dvec3 l(0.0);
  const glm::dvec3 tau_end = ref.optical_depth(pos, dir, sp.t0, sp.t1);
  const glm::dvec3 t_end = glm::exp(-tau_end);
  const glm::dvec3 hit_prob = glm::dvec3(1.0) - t_end;
  if (sp.ground) {
    const glm::dvec3 xg = pos + sp.t1 * dir;
    const glm::dvec3 n = glm::normalize(xg);
    const glm::dvec3 bounce = around(n, std::sqrt(1.0 - rng.uniform()), 2.0 * kPiD * rng.uniform());
    l += trace(ref, n * (ref.R_ + 1e-3), bounce, t_end * glm::dvec3(ref.m_.ground_albedo), 2, s, e, max_bounces, rng);
  }
  const int channel = std::min(2, int(rng.uniform() * 3.0));
  if (!(hit_prob[channel] > 0.0)) return l;
  const double target = -std::log(1.0 - rng.uniform() * hit_prob[channel]);
  const FreeFlight f = fly(ref, pos, dir, sp, channel, target);
  if (!f.collided) return l;  // rounding at the far end
  const double t = f.t;
  const Medium& at = f.medium;
  const glm::dvec3 tr = glm::exp(-f.tau);
  double pdf = 0.0;
  for (int k = 0; k < 3; ++k)
    if (hit_prob[k] > 0.0) pdf += at.extinction[k] * tr[k] / hit_prob[k];
  pdf /= 3.0;
  if (!(pdf > 0.0)) return l;
  const glm::dvec3 x = pos + t * dir;
  glm::dvec3 throughput = tr / pdf;
  scatter(ref, at, dir, throughput, rng);
  return l + trace(ref, x, dir, throughput, 2, s, e, max_bounces, rng);
}

glm::dvec3 trace(const Reference& ref, glm::dvec3 pos, glm::dvec3 dir, glm::dvec3 throughput, int first_vertex,
                 const glm::dvec3& s, const glm::dvec3& e, int max_bounces, Rng& rng) {
  glm::dvec3 l(0.0);
  const glm::dvec3 albedo(ref.m_.ground_albedo);
  for (int vertex = first_vertex; vertex <= max_bounces; ++vertex) {
    const Reference::Span sp = ref.span(pos, dir);
    if (!sp.valid) break;
    // Free flight: one channel's extinction, chosen uniformly (one-sample spectral MIS).
    const int channel = std::min(2, int(rng.uniform() * 3.0));
    const double target = -std::log(1.0 - rng.uniform());
    const FreeFlight f = fly(ref, pos, dir, sp, channel, target);
    const double t = f.t;
    const bool collided = f.collided;
    const Medium& at = f.medium;
    const glm::dvec3 tr = glm::exp(-f.tau);
    if (collided) {
      const glm::dvec3 x = pos + t * dir;
      const double pdf_t = mean(at.extinction * tr);
      if (!(pdf_t > 0.0)) break;
      const glm::dvec3 w = throughput * tr / pdf_t;
      if (vertex >= 2) {
        const double nu = glm::dot(dir, s);
        l += w * (at.rayleigh * rayleigh_phase(nu) + at.mie * ref.phase_mie(nu)) * ref.sun(x, s) * e;
      }
      // Direction: uniform sphere (Rayleigh proxy) or the Mie proxy, mixed by scattering share.
      throughput = w;
      scatter(ref, at, dir, throughput, rng);
      pos = x;
    } else {
      const double p_none = mean(tr);
      if (!(p_none > 0.0)) break;
      throughput *= tr / p_none;
      if (!sp.ground) break;  // escaped to space
      const glm::dvec3 xg = pos + sp.t1 * dir;
      const glm::dvec3 n = glm::normalize(xg);
      if (vertex >= 2) l += throughput * albedo / kPiD * ref.sun(xg, s) * std::max(0.0, glm::dot(n, s)) * e;
      // Cosine-weighted bounce: BRDF * cos / pdf = albedo.
      dir = around(n, std::sqrt(1.0 - rng.uniform()), 2.0 * kPiD * rng.uniform());
      throughput *= albedo;
      pos = n * (ref.R_ + 1e-3);
    }
    if (vertex >= 3) {  // Russian roulette
      const double keep = std::min(1.0, max_component(throughput));
      if (rng.uniform() >= keep) break;
      throughput /= keep;
    }
  }
  return l;
}

// Second moments of a pixel's path estimates (linear sRGB and its luminance),
// for the standard errors of its luminance and of its colour ratios.
struct PathCovariance {
  double yy = 0.0;
  glm::dvec3 cc{0.0};  // r r, g g, b b
  double rg = 0.0, bg = 0.0;
  void add(const PathCovariance& o) {
    yy += o.yy;
    cc += o.cc;
    rg += o.rg;
    bg += o.bg;
  }
};

struct PathMoments {
  int paths = 0;
  glm::dvec3 sum{0.0};
  double y = 0.0;
  PathCovariance sq;  // sums of the products
  void add(const glm::dvec3& c) {
    const double lum = luminance(c);
    ++paths;
    sum += c;
    y += lum;
    sq.add({lum * lum, c * c, c.r * c.g, c.b * c.g});
  }
  void merge(const PathMoments& o) {
    paths += o.paths;
    sum += o.sum;
    y += o.y;
    sq.add(o.sq);
  }
  // The sample covariances times the path count (0 below two paths).
  PathCovariance covariance_times_paths() const {
    if (paths < 2) return {};
    const double m = paths, f = m / (m - 1.0);
    const glm::dvec3 mean = sum / m;
    const double y_mean = y / m;
    PathCovariance c;
    c.yy = std::max(0.0, (sq.yy / m - y_mean * y_mean) * f) * m;
    c.cc = glm::max(glm::dvec3(0.0), (sq.cc / m - mean * mean) * f) * m;
    c.rg = (sq.rg / m - mean.r * mean.g) * f * m;
    c.bg = (sq.bg / m - mean.b * mean.g) * f * m;
    return c;
  }
};

}  // namespace

glm::dvec3 reference_transmittance(const AtmosphereModel& model, const glm::dvec3& point, const glm::dvec3& dir) {
  return Reference(model).to_top(point, glm::normalize(dir));
}

ReferenceImage render_reference(const AtmosphereModel& model, const ReferenceView& view,
                                const ReferenceSettings& settings, JobSystem& jobs,
                                const std::function<void(size_t, size_t)>& progress) {
  const SpectralSampling& sampling = settings.sampling;
  const int g_count = sampling.groups();
  if (g_count < 1 || sampling.wavelengths_nm.size() != size_t(g_count) * 3 ||
      sampling.weights.size() != sampling.wavelengths_nm.size())
    throw std::invalid_argument("render_reference: the sampling needs wavelengths in groups of three, one weight each");
  // One model per group (the RGB sampling: the model itself); the Reference
  // objects refer to these, so the vector is complete before they are made.
  std::vector<AtmosphereModel> models;
  for (int g = 0; g < g_count; ++g) {
    const size_t w = size_t(g) * 3;
    models.push_back(sampling.rgb ? model
                                  : model_at_wavelengths(model, {sampling.wavelengths_nm[w], sampling.wavelengths_nm[w + 1],
                                                                 sampling.wavelengths_nm[w + 2]}));
  }
  std::vector<GroupCoefficients> coefficients;
  for (const AtmosphereModel& m : models) coefficients.emplace_back(m);
  const Reference geometry(models.front());  // radii, density profiles, phase and sun disk: the same in every group
  // The paths' groups interleave the wavelengths: path group g holds the
  // sampling's wavelengths g, g + G and g + 2G. Over a sampling ordered by
  // wavelength each path then spans the spectrum (its three channels add up to
  // a colour, not a narrow band whose sRGB weights are partly negative), which
  // keeps the paths' colour and luminance noise low. The RGB sampling (G = 1)
  // keeps its own channels.
  std::vector<std::array<size_t, 3>> path_index(static_cast<size_t>(g_count));
  std::vector<AtmosphereModel> path_models;
  for (int g = 0; g < g_count; ++g) {
    for (size_t c = 0; c < 3; ++c) path_index[size_t(g)][c] = size_t(g) + c * size_t(g_count);
    const std::array<size_t, 3>& w = path_index[size_t(g)];
    path_models.push_back(sampling.rgb ? model
                                       : model_at_wavelengths(model, {sampling.wavelengths_nm[w[0]], sampling.wavelengths_nm[w[1]],
                                                                      sampling.wavelengths_nm[w[2]]}));
  }
  std::vector<Reference> refs;
  for (const AtmosphereModel& m : path_models) refs.emplace_back(m);
  // A path group's values (per unit sun at each of its wavelengths) to linear sRGB.
  const auto group_rgb = [&](int g, const glm::dvec3& v) {
    const std::array<size_t, 3>& w = path_index[size_t(g)];
    return sampling.weights[w[0]] * v.x + sampling.weights[w[1]] * v.y + sampling.weights[w[2]] * v.z;
  };

  const size_t n = view.directions.size();
  ReferenceImage out;
  out.radiance.assign(n, glm::vec3(0.0f));
  out.noise.assign(n, 0.0f);
  out.ratio_noise.assign(n, glm::vec2(0.0f));
  glm::dvec3 o = view.origin;
  const double r = glm::length(o);
  if (r < model.bottom_radius + 0.01) o = o / r * (model.bottom_radius + 0.01);  // below the ground: clamp
  const glm::dvec3 s = glm::normalize(glm::dvec3(view.sun_direction));
  const glm::dvec3 e(view.sun_illuminance);
  const glm::dvec3 unit_sun(1.0);
  std::atomic<size_t> done{0};
  const size_t grain = 64;
  jobs.parallel_for("atmosphere.reference", n, grain, [&](size_t begin, size_t end) {
    std::vector<glm::dvec3> groups;
    const size_t gs = size_t(g_count);
    std::vector<PathMoments> group_moments(gs);
    for (size_t i = begin; i < end; ++i) {
      const glm::dvec3 d = glm::normalize(glm::dvec3(view.directions[i]));
      glm::dvec3 l(0.0);
      if (settings.single_scattering) {
        single_scattering(geometry, coefficients, o, d, s, groups);
        l += to_rgb(sampling, groups) * e;
      }
      if (settings.multiple_scattering && settings.samples_per_pixel > 0) {
        // Path k takes group (k + offset) mod G, weighted by G: the groups are
        // stratified over the pixel's paths, the offset (from the pixel's seed)
        // makes each group's share unbiased when G does not divide the paths.
        std::fill(group_moments.begin(), group_moments.end(), PathMoments{});
        Rng pixel_rng{settings.seed * 0x9E3779B97F4A7C15ull ^ (uint64_t(i) * 0xD1B54A32D192ED03ull)};
        const int offset = g_count > 1 ? int(pixel_rng.next_u64() % uint64_t(g_count)) : 0;
        const int spp = settings.samples_per_pixel;
        for (int k = 0; k < spp; ++k) {
          const int g = (k + offset) % g_count;
          Rng rng{settings.seed * 0x100000001B3ull ^ (uint64_t(i) << 20) ^ uint64_t(k)};
          rng.next_u64();
          const glm::dvec3 p = multiple_scattering_path(refs[size_t(g)], o, d, s, unit_sun, settings.max_bounces, rng);
          group_moments[size_t(g)].add(group_rgb(g, p) * double(g_count) * e);
        }
        PathMoments all;
        for (const PathMoments& m : group_moments) all.merge(m);
        l += all.sum / double(spp);
        // The covariance of the stratified estimate: each group's sample
        // covariance, weighted by its paths (one group: the plain sample
        // covariance). A group with a single path has none of its own: then the
        // covariance of all paths together stands in (an upper bound).
        bool stratified = true;
        for (const PathMoments& m : group_moments) stratified = stratified && m.paths != 1;
        PathCovariance cov;
        if (stratified) {
          for (const PathMoments& m : group_moments) cov.add(m.covariance_times_paths());
        } else {
          cov = all.covariance_times_paths();
        }
        const double inv = 1.0 / (double(spp) * double(spp));  // of the mean of spp paths
        out.noise[i] = float(std::sqrt(std::max(0.0, cov.yy * inv)));
        // First order: var(a/g) / (a/g)^2 = var(a)/a^2 + var(g)/g^2 - 2 cov(a, g)/(a g).
        const auto ratio = [&](int a, double aa, double ag) {
          if (!(l[a] > 0.0) || !(l.g > 0.0)) return 0.0f;
          const double v = (aa / (l[a] * l[a]) + cov.cc.g / (l.g * l.g) - 2.0 * ag / (l[a] * l.g)) * inv;
          return float(std::sqrt(std::max(0.0, v)));
        };
        out.ratio_noise[i] = glm::vec2(ratio(0, cov.cc.r, cov.rg), ratio(2, cov.cc.b, cov.bg));
      }
      out.radiance[i] = glm::vec3(l);
    }
    const size_t total = done.fetch_add(end - begin) + (end - begin);
    if (progress) progress(total, n);
  });
  return out;
}

}  // namespace cr

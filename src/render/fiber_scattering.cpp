#include "render/fiber_scattering.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/parallel.hpp"

namespace wisp {

Vec3f eumelanin_absorption() {
    return {0.419f, 0.697f, 1.37f};
}
Vec3f pheomelanin_absorption() {
    return {0.187f, 0.4f, 1.05f};
}

Vec3f melanin_absorption(const Melanin& m) {
    return std::max(0.f, m.eumelanin) * eumelanin_absorption() +
           std::max(0.f, m.pheomelanin) * pheomelanin_absorption();
}

namespace {

// k(β_n) of Chiang et al. eq. 9.
float color_fit(float b) {
    return 5.969f - 0.215f * b + 2.532f * b * b - 10.73f * b * b * b + 5.574f * b * b * b * b +
           0.245f * b * b * b * b * b;
}

}  // namespace

Vec3f absorption_from_color(const Vec3f& c, float beta_n) {
    const float fit = color_fit(beta_n);
    Vec3f sigma;
    for (int k = 0; k < 3; ++k) {
        const float x = std::log(std::clamp(c[k], 1e-4f, 1.f)) / fit;
        sigma[k] = x * x;
    }
    return sigma;
}

Vec3f color_from_absorption(const Vec3f& sigma_a, float beta_n) {
    const float fit = color_fit(beta_n);
    Vec3f c;
    for (int k = 0; k < 3; ++k)
        c[k] = std::exp(-fit * std::sqrt(std::max(sigma_a[k], 0.f)));
    return c;
}

Melanin melanin_from_color(const Vec3f& c, float beta_n) {
    const float fit = color_fit(beta_n);
    const Vec3f e = eumelanin_absorption(), p = pheomelanin_absorption();
    // The redness is fitted to red and green alone: blue, which both pigments absorb most, is
    // where a colour picked by eye strays furthest from any hair's (an auburn's blue, a
    // blonde's, ask for more than either pigment lets through), and it would pull the fit off
    // the red-to-green balance that makes a hair red or brown.
    double target[3];  // √σa each channel asks for: −ln c / k
    for (int k = 0; k < 3; ++k)
        target[k] = -std::log(std::clamp(static_cast<double>(c[k]), 1e-8, 1.0)) / fit;
    // As concentrations q·(1 − r) and q·r, each channel's √σa is √q · √((1 − r)·e + r·p). Red
    // over green fixes r, exactly where the pigments can give the colour's ratio and at the
    // nearer pigment alone where they cannot (the ratio is monotonic in r):
    //   ((1 − r)·e_R + r·p_R) = ρ²·((1 − r)·e_G + r·p_G),  ρ = √σa_R / √σa_G.
    // Eumelanin's ratio is the higher: a colour redder than pheomelanin is pheomelanin, one
    // less red than eumelanin (a grey, a black) eumelanin.
    double r = 0;
    if (target[1] > 0) {
        const double rho2 = (target[0] / target[1]) * (target[0] / target[1]);
        if (rho2 <= p[0] / p[1])
            r = 1;
        else if (rho2 < e[0] / e[1])
            r = (rho2 * e[1] - e[0]) / ((p[0] - e[0]) - rho2 * (p[1] - e[1]));
    }
    double shape[3];
    for (int k = 0; k < 3; ++k)
        shape[k] = std::sqrt((1 - r) * e[k] + r * p[k]);
    // Then the amount that gives the colour's luminance (Rec. 709) exactly: Newton on √q, the
    // luminance being convex and falling in it, from green's own √q.
    const double w[3] = {0.2126, 0.7152, 0.0722};
    double want = 0;
    for (int k = 0; k < 3; ++k)
        want += w[k] * std::clamp(static_cast<double>(c[k]), 1e-8, 1.0);
    double g = std::max(0.0, target[1] / shape[1]);
    for (int iteration = 0; iteration < 32; ++iteration) {
        double y = 0, dy = 0;
        for (int k = 0; k < 3; ++k) {
            const double term = w[k] * std::exp(-fit * g * shape[k]);
            y += term;
            dy -= fit * shape[k] * term;
        }
        if (dy >= 0) break;  // white: no melanin
        const double next = std::max(0.0, g - (y - want) / dy);
        const bool done = std::abs(next - g) <= 1e-9 * (1 + g);
        g = next;
        if (done) break;
    }
    return {static_cast<float>(g * g * (1 - r)), static_cast<float>(g * g * r)};
}

namespace {

// Fresnel reflectance of unpolarized light at a dielectric of index η from the outside, at
// incidence cosine cos_i.
float fresnel_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, 0.f, 1.f);
    const float sin_t2 = (1.f - cos_i * cos_i) / (eta * eta);
    if (sin_t2 >= 1.f) return 1.f;
    const float cos_t = std::sqrt(1.f - sin_t2);
    const float parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (parallel * parallel + perpendicular * perpendicular);
}

// The modified Bessel function I₀(x), from its series, summed until a term adds under 10⁻¹²
// of the sum (log_bessel_i0 takes over above x = 12).
double bessel_i0(double x) {
    double sum = 0, term = 1;
    const double q = 0.25 * x * x;
    for (int i = 1; i <= 24 && term > 1e-12 * sum; ++i) {
        sum += term;
        term *= q / (static_cast<double>(i) * i);
    }
    return sum + term;
}

double log_bessel_i0(double x) {
    if (x > 12) return x + 0.5 * (-std::log(2 * M_PI) + std::log(1 / x) + 1 / (8 * x));
    return std::log(bessel_i0(x));
}

// The logistic distribution of scale s, and it trimmed to [−π, π] and renormalized.
double logistic(double x, double s) {
    x = std::abs(x);
    const double e = std::exp(-x / s);
    return e / (s * (1 + e) * (1 + e));
}

double logistic_cdf(double x, double s) {
    return 1 / (1 + std::exp(-x / s));
}

double trimmed_logistic(double x, double s) {
    return logistic(x, s) / (logistic_cdf(M_PI, s) - logistic_cdf(-M_PI, s));
}

// φ wrapped to [−π, π].
double wrap(double phi) {
    while (phi > M_PI)
        phi -= 2 * M_PI;
    while (phi < -M_PI)
        phi += 2 * M_PI;
    return phi;
}

// acos to within 7·10⁻⁵ rad (Abramowitz & Stegun 4.4.45), without a libm call.
inline float fast_acos(float x) {
    const float a = std::abs(x);
    const float r = std::sqrt(std::max(0.f, 1.f - a)) *
                    (1.5707288f + a * (-0.2121144f + a * (0.0742610f - 0.0187293f * a)));
    return x >= 0.f ? r : kPi - r;
}

// e^x of four floats to within 2·10⁻⁷ of it, 0 below −87 (where it is under 10⁻³⁷) and for
// NaN: 2^i · e^r with r = x − i·ln 2 in [−ln 2/2, ln 2/2] (ln 2 in two parts, so that r is
// exact) and e^r by its Taylor series to r⁶. A third of the instructions of Eigen's exp,
// which handles what the shading never asks (denormals, overflow); plain SSE2 arithmetic, so
// the same bits on every x86-64.
inline Eigen::Array4f exp4(const Eigen::Array4f& x_in) {
#if defined(__SSE2__)
    const __m128 lo = _mm_set1_ps(-87.f);
    __m128 x = _mm_loadu_ps(x_in.data());
    const __m128 inside = _mm_cmpgt_ps(x, lo);  // false for NaN and below −87
    x = _mm_min_ps(_mm_max_ps(x, lo), _mm_set1_ps(88.f));
    const __m128i i = _mm_cvtps_epi32(_mm_mul_ps(x, _mm_set1_ps(1.44269504f)));  // nearest
    const __m128 fi = _mm_cvtepi32_ps(i);
    const __m128 r = _mm_add_ps(_mm_sub_ps(x, _mm_mul_ps(fi, _mm_set1_ps(0.693359375f))),
                                _mm_mul_ps(fi, _mm_set1_ps(2.12194440e-4f)));
    __m128 p = _mm_set1_ps(1.f / 720.f);
    for (const float c : {1.f / 120.f, 1.f / 24.f, 1.f / 6.f, 0.5f, 1.f, 1.f})
        p = _mm_add_ps(_mm_mul_ps(p, r), _mm_set1_ps(c));
    const __m128 two_i =
        _mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(i, _mm_set1_epi32(127)), 23));
    Eigen::Array4f out;
    _mm_storeu_ps(out.data(), _mm_and_ps(inside, _mm_mul_ps(p, two_i)));
    return out;
#else
    return (x_in > -87.f).select(x_in.min(88.f).exp(), 0.f);
#endif
}

// asin to within 7·10⁻⁵ rad, by fast_acos.
inline float fast_asin(float x) {
    return 0.5f * kPi - fast_acos(x);
}

// d'Eon et al.'s longitudinal lobe M_p for variance v (the von Mises–Fisher distribution on θ),
// normalized over ∫ M cos θ_i dθ_i = 1.
float longitudinal_scattering(float sin_i, float cos_i, float sin_o, float cos_o, float v) {
    const double a = static_cast<double>(cos_i) * cos_o / v;
    const double b = static_cast<double>(sin_i) * sin_o / v;
    // For small v, 2v·sinh(1/v) overflows: in logs, 1/(2v sinh(1/v)) ≈ e^(−1/v)/v.
    const double m = v <= 0.1 ? std::exp(log_bessel_i0(a) - b - 1.0 / v - std::log(v))
                              : std::exp(-b) * bessel_i0(a) / (2 * v * std::sinh(1.0 / v));
    return static_cast<float>(m);
}

}  // namespace

FiberScattering::FiberScattering(const FiberParams& params) : params_(params) {
    const double eta = params.eta;
    const double bm = std::clamp(params.beta_m, 0.1f, 1.f);
    const double bn = std::clamp(params.beta_n, 0.1f, 1.f);
    // Chiang et al. 2016 eqs. 7 and 8: the variance and the logistic scale that give lobes
    // that look as rough as β says.
    const double v0 = std::pow(0.726 * bm + 0.812 * bm * bm + 3.7 * std::pow(bm, 20), 2);
    const double v[3] = {v0, 0.25 * v0, 4 * v0};
    const double s =
        std::sqrt(M_PI / 8) * (0.265 * bn + 1.194 * bn * bn + 5.372 * std::pow(bn, 22));
    const double alpha = params.alpha * M_PI / 180;
    const double shift[3] = {2 * alpha, -alpha, -4 * alpha};
    for (int p = 0; p < 3; ++p) {
        tilt_sin_[p] = static_cast<float>(std::sin(shift[p]));
        tilt_cos_[p] = static_cast<float>(std::cos(shift[p]));
    }

    // The azimuthal tables: h = sin γ_o over γ_o in [−π/2, π/2] (dh = cos γ_o dγ_o, which
    // samples the fibre's edges, where the exit azimuth moves fastest, as densely as its
    // middle).
    constexpr int kH = 256;
    std::vector<float> n_table(3 * kThetaO * kPhi),
        l_table(3 * kThetaO * kPhi);  // N̄_p, L̄_p at (p, row, φ)
    // Per row, the rest (p ≥ 3) without absorption, the mean Fresnel factor f̄ and the mean
    // path l̄ through the fibre: A_3 ≈ F̄₃ · T³ (1 − f̄) / (1 − f̄ T), T = e^−σa·l̄.
    std::vector<float> rest_table(kThetaO), rest_f_table(kThetaO), rest_l_table(kThetaO);
    // Rows apart (each writes only its own entries: the same tables at any thread count).
    parallel_for(kThetaO, [&](size_t row_index) {
        const int row = static_cast<int>(row_index);
        std::vector<double> n(3 * kPhi), nl(3 * kPhi);
        const double sin_o = std::min(0.9999, static_cast<double>(row) / (kThetaO - 1));
        const double cos_o = std::sqrt(1 - sin_o * sin_o);
        // The fibre seen in the plane normal to it: the index for the projected path (Bravais).
        const double eta_p = std::sqrt(eta * eta - sin_o * sin_o) / cos_o;
        const double sin_t = sin_o / eta, cos_t = std::sqrt(1 - sin_t * sin_t);
        double rest = 0, rest_f = 0, rest_l = 0, weight = 0;
        for (int k = 0; k < kH; ++k) {
            const double gamma_o = M_PI * ((k + 0.5) / kH - 0.5);
            const double h = std::sin(gamma_o);
            const double w = 0.5 * std::cos(gamma_o) * (M_PI / kH);  // ½ dh
            const double gamma_t = std::asin(std::clamp(h / eta_p, -1.0, 1.0));
            const double f = fresnel_dielectric(static_cast<float>(cos_o * std::cos(gamma_o)),
                                                static_cast<float>(eta));
            const double path = 2 * std::cos(gamma_t) / cos_t;
            const double fp[3] = {f, (1 - f) * (1 - f), (1 - f) * (1 - f) * f};
            for (int p = 0; p < 3; ++p) {
                const double centre = 2 * p * gamma_t - 2 * gamma_o + p * M_PI;
                for (int j = 0; j < kPhi; ++j) {
                    const double phi = M_PI * j / (kPhi - 1);
                    const double value = w * fp[p] * trimmed_logistic(wrap(phi - centre), s);
                    n[p * kPhi + j] += value;
                    nl[p * kPhi + j] += value * p * path;
                }
            }
            rest += w * (1 - f) * f * f;
            rest_f += w * f;
            rest_l += w * path;
            weight += w;
        }
        for (int p = 0; p < 3; ++p)
            for (int j = 0; j < kPhi; ++j) {
                const size_t at = (static_cast<size_t>(p) * kThetaO + row) * kPhi + j;
                n_table[at] = static_cast<float>(n[p * kPhi + j]);
                l_table[at] = n[p * kPhi + j] > 0
                                  ? static_cast<float>(nl[p * kPhi + j] / n[p * kPhi + j])
                                  : 0.f;
            }
        rest_table[row] = static_cast<float>(rest / weight);
        rest_f_table[row] = static_cast<float>(rest_f / weight);
        rest_l_table[row] = static_cast<float>(rest_l / weight);
    });

    azimuthal_.resize(2 * kThetaO * kPhi);
    for (int row = 0; row < kThetaO; ++row)
        for (int j = 0; j < kPhi; ++j) {
            const size_t at = static_cast<size_t>(row) * kPhi + j, stride = kThetaO * kPhi;
            azimuthal_[2 * at] = {n_table[at], n_table[stride + at], n_table[2 * stride + at],
                                  l_table[stride + at]};
            azimuthal_[2 * at + 1] = {l_table[2 * stride + at], rest_table[row], rest_f_table[row],
                                      rest_l_table[row]};
        }

    // The albedos' shares, from row 0 (light and eye across the fibre): φ < π/2 is back.
    for (int p = 0; p < 3; ++p) {
        double fwd = 0, back = 0, fwd_l = 0, back_l = 0;
        for (int j = 0; j + 1 < kPhi; ++j) {
            // Trapezoids over [0, π], doubled for [−π, 0].
            const double dphi = M_PI / (kPhi - 1);
            const double phi = (j + 0.5) * dphi;
            const size_t at = static_cast<size_t>(p) * kThetaO * kPhi + j;
            const double value = dphi * (n_table[at] + n_table[at + 1]);  // 2 · ½ (a + b) dφ
            const double path = 0.5 * (l_table[at] + l_table[at + 1]);
            if (phi < 0.5 * M_PI) {
                back += value;
                back_l += value * path;
            } else {
                fwd += value;
                fwd_l += value * path;
            }
        }
        forward_[p] = static_cast<float>(fwd);
        backward_[p] = static_cast<float>(back);
        forward_path_[p] = fwd > 0 ? static_cast<float>(fwd_l / fwd) : 0.f;
        backward_path_[p] = back > 0 ? static_cast<float>(back_l / back) : 0.f;
    }
    back_variance_ = static_cast<float>(0.5 * (v[0] + v[2]));
    forward_variance_ = static_cast<float>(v[1]);

    // The longitudinal tables, on sin θ ∈ [−1, 1] nodes, rows apart. The rest (p ≥ 3) has
    // TRT's variance: it reads TRT's table, untilted.
    m_.assign(3 * kM * kM, 0.f);
    parallel_for(3 * kM, [&](size_t k) {
        const int p = static_cast<int>(k) / kM, i = static_cast<int>(k) % kM;
        const float sin_i = -1.f + 2.f * i / (kM - 1), cos_i = std::sqrt(1 - sin_i * sin_i);
        for (int o = 0; o < kM; ++o) {
            const float sin_o = -1.f + 2.f * o / (kM - 1), cos_o = std::sqrt(1 - sin_o * sin_o);
            m_[k * kM + o] =
                longitudinal_scattering(sin_i, cos_i, sin_o, cos_o, static_cast<float>(v[p]));
        }
    });
}

FiberScattering::View FiberScattering::view(const Vec3f& tangent, const Vec3f& to_eye) const {
    View v;
    v.t = tangent;
    v.sin_o = std::clamp(tangent.dot(to_eye), -1.f, 1.f);
    v.cos_o = std::sqrt(std::max(0.f, 1.f - v.sin_o * v.sin_o));
    v.theta_o = fast_asin(v.sin_o);
    v.op = to_eye - v.sin_o * tangent;
    v.op2 = v.op.squaredNorm();
    const float fy = std::abs(v.sin_o) * (kThetaO - 1);
    v.row = std::min(static_cast<int>(fy), kThetaO - 2);
    v.row_w = fy - static_cast<float>(v.row);
    const float fm = (v.sin_o + 1.f) * 0.5f * (kM - 1);
    v.m_col = std::min(static_cast<int>(fm), kM - 2);
    v.m_col_w = fm - static_cast<float>(v.m_col);
    return v;
}

Vec3f FiberScattering::eval(const View& v, const Vec3f& to_light, const Vec3f& sigma_a) const {
    const float sin_i = std::clamp(v.t.dot(to_light), -1.f, 1.f);
    const float cos_i = std::sqrt(std::max(0.f, 1.f - sin_i * sin_i));
    const Vec3f ip = to_light - sin_i * v.t;
    const float norm2 = ip.squaredNorm() * v.op2;
    const float cos_phi =
        norm2 > 1e-16f ? std::clamp(ip.dot(v.op) / std::sqrt(norm2), -1.f, 1.f) : 1.f;
    const float fx = fast_acos(cos_phi) * (1.f / kPi) * (kPhi - 1);
    const int col = std::min(static_cast<int>(fx), kPhi - 2);
    const float wx = fx - static_cast<float>(col), wy = v.row_w;
    // The azimuthal tables' eight values at once, bilinearly.
    const Eigen::Array4f* a = &azimuthal_[2 * (static_cast<size_t>(v.row) * kPhi + col)];
    const Eigen::Array4f* b = a + 2 * kPhi;
    auto azimuthal = [&](int k) -> Eigen::Array4f {
        const Eigen::Array4f top = a[k] + (a[k + 2] - a[k]) * wx;
        const Eigen::Array4f bottom = b[k] + (b[k + 2] - b[k]) * wx;
        return top + (bottom - top) * wy;
    };
    const Eigen::Array4f lobes = azimuthal(0), more = azimuthal(1);
    auto longitudinal = [&](int p, float sin_ip) {
        const float fi = (std::clamp(sin_ip, -1.f, 1.f) + 1.f) * 0.5f * (kM - 1);
        const int i = std::min(static_cast<int>(fi), kM - 2);
        const float wi = fi - static_cast<float>(i);
        const float* a = &m_[(static_cast<size_t>(p) * kM + i) * kM + v.m_col];
        const float* b = a + kM;
        const float top = a[0] + (a[1] - a[0]) * v.m_col_w;
        const float bottom = b[0] + (b[1] - b[0]) * v.m_col_w;
        return top + (bottom - top) * wi;
    };
    auto tilted = [&](int p) { return sin_i * tilt_cos_[p] + cos_i * tilt_sin_[p]; };
    const float r = longitudinal(0, tilted(0)) * lobes[0];
    const float tt = longitudinal(1, tilted(1)) * lobes[1];
    const float trt = longitudinal(2, tilted(2)) * lobes[2];
    const float l_tt = lobes[3], l_trt = more[0];
    // The rest: F̄₃ · T³ (1 − f̄) / (1 − f̄ T), spread evenly over the azimuth.
    const float rest = more[1], f = more[2], l = more[3];
    const float m_rest = longitudinal(2, sin_i) * (1.f / (2.f * kPi));
    // The three channels at once.
    const Eigen::Array4f minus_sigma(-sigma_a[0], -sigma_a[1], -sigma_a[2], 0.f);
    const Eigen::Array4f t = exp4(minus_sigma * l);
    const Eigen::Array4f out = r + tt * exp4(minus_sigma * l_tt) + trt * exp4(minus_sigma * l_trt) +
                               (m_rest * rest * (1.f - f)) * t * t * t / (1.f - f * t);
    return {out[0], out[1], out[2]};
}

FiberScattering::Albedo FiberScattering::albedo(const Vec3f& sigma_a) const {
    Albedo a;
    // The rest (p ≥ 3) at row 0, split evenly between forward and back.
    // The rest's terms at row 0, from the azimuthal table's second set (any column).
    const Eigen::Array4f& rest0 = azimuthal_[1];
    const float t_rest_l = rest0[3], f = rest0[2];
    for (int k = 0; k < 3; ++k) {
        const float t = std::exp(-sigma_a[k] * t_rest_l);
        const float rest = 0.5f * rest0[1] * t * t * t * (1.f - f) / (1.f - f * t);
        float fwd = rest, back = rest;
        for (int p = 0; p < 3; ++p) {
            fwd += forward_[p] * std::exp(-sigma_a[k] * forward_path_[p]);
            back += backward_[p] * std::exp(-sigma_a[k] * backward_path_[p]);
        }
        a.forward[k] = std::min(fwd, 0.999f);
        a.backward[k] = back;
        a.log_forward[k] = std::log(std::max(a.forward[k], 1e-6f));
        const float ff = a.forward[k] * a.forward[k], one = 1.f - ff;
        a.back_scatter[k] = back * ff / one + back * back * back * ff / (one * one * one);
    }
    return a;
}

Vec3f FiberScattering::multiple(const View& v, const Vec3f& to_light, const Albedo& a, float fibres,
                                float behind) const {
    const float sin_i = std::clamp(v.t.dot(to_light), -1.f, 1.f);
    const float cos_i = std::sqrt(std::max(0.f, 1.f - sin_i * sin_i));
    // θ_h = (θ_i + θ_o)/2; cos² θ_d, θ_d = (θ_o − θ_i)/2, is (1 + cos(θ_o − θ_i))/2.
    const float theta_h = 0.5f * (fast_asin(sin_i) + v.theta_o);
    const float cos_d2 = 0.5f * (1.f + cos_i * v.cos_o + sin_i * v.sin_o);
    const float n = std::max(0.f, fibres);
    // The longitudinal spread: the fibres' back-scattering, widened by each forward pass.
    const float variance = back_variance_ + n * forward_variance_;
    // Four exponentials at a time: ā_f^n per channel and e^−n; ā_f^2m per channel (0 for hair
    // without end, whose exponent is −∞) and the spread's Gaussian.
    const float m2 = 2.f * std::max(0.f, behind);
    const Eigen::Array4f e1 =
        exp4(Eigen::Array4f(n * a.log_forward[0], n * a.log_forward[1], n * a.log_forward[2], -n));
    const Eigen::Array4f e2 =
        exp4(Eigen::Array4f(m2 * a.log_forward[0], m2 * a.log_forward[1], m2 * a.log_forward[2],
                            -0.5f * theta_h * theta_h / variance));
    const float g = e2[3] / std::sqrt(2.f * kPi * variance);
    const float shape = cos_i * g / (kPi * std::max(cos_d2, 1e-3f));
    const float direct = e1[3];
    Vec3f out;
    for (int k = 0; k < 3; ++k) {
        const float through = e1[k], layers = 1.f - e2[k];
        // Back-scattered by the fibres behind the point, of the light that reached it; and
        // the forward-scattered light that reached it (beyond what came straight through),
        // sent back by the fibre itself.
        out[k] =
            shape * (2.f * params_.back_density * a.back_scatter[k] * layers * through +
                     params_.forward_density * a.backward[k] * std::max(0.f, through - direct));
    }
    return out;
}

std::shared_ptr<const FiberScattering> fiber_scattering(const FiberParams& params) {
    static std::mutex mutex;
    static FiberParams last;
    static std::shared_ptr<const FiberScattering> tables;
    const auto same = [](const FiberParams& a, const FiberParams& b) {
        return a.eta == b.eta && a.beta_m == b.beta_m && a.beta_n == b.beta_n &&
               a.alpha == b.alpha && a.back_density == b.back_density &&
               a.forward_density == b.forward_density;
    };
    const std::lock_guard lock(mutex);
    if (!tables || !same(last, params)) {
        tables = std::make_shared<const FiberScattering>(params);
        last = params;
    }
    return tables;
}

}  // namespace wisp

#pragma once
// Light scattered by one hair fibre: the far-field model of Chiang, Bitterli, Tappan and
// Burley ("A Practical and Controllable Hair and Fur Model for Production Path Tracing",
// EGSR 2016), the model of Cycles' Principled Hair BSDF and pbrt-v4's hair material, built
// on d'Eon et al. 2011 and Marschner et al. 2003.
//
// A fibre is a dielectric cylinder (η = 1.55) whose interior absorbs σa per unit of its
// radius, with the cuticle's scales tilted by α toward the tip. Light leaves it by paths p:
// R (p = 0, reflected at the surface), TT (1, through), TRT (2, in, reflected off the back,
// out) and the rest (p ≥ 3) summed. Each path is a product
//
//   S_p(ω_i, ω_o) = M_p(θ_i, θ_o) · N_p(φ; h) · A_p(h)
//
// of a longitudinal lobe M_p (θ from the plane normal to the fibre; d'Eon's von Mises–Fisher
// form, of variance v_p from the longitudinal roughness β_m, around θ_i shifted by the
// scales' tilt: −2α for R, α for TT, 4α for TRT), an azimuthal lobe N_p (a logistic of scale
// s from the azimuthal roughness β_n, around the exit azimuth of the path that enters at
// offset h across the fibre) and its attenuation A_p: Fresnel at each interface and e^−σa·l
// along each of its p passes of length l(h) = 2 cos γ_t / cos θ_t.
//
// A rasterizer draws a fibre thinner than a pixel without knowing h: the far field averages
// over h ∈ [−1, 1]. That average is tabulated once per set of roughnesses, absorption aside:
//   N̄_p(φ, θ_o) = ½ ∫ F_p(h) N_p(φ; h) dh,   F_p the Fresnel part of A_p,
//   L̄_p(φ, θ_o) = ½ ∫ F_p N_p · p·l(h) dh / N̄_p, the mean path inside the fibre,
// and the absorption of a strand applied as e^−σa·L̄_p: exact without absorption (so the
// model conserves energy: a white furnace sums to 1) and to first order in σa, and where
// absorption is strong only R, which it does not touch, is left. M_p is tabulated over
// (sin θ_i, sin θ_o).
//
// Units: S is per steradian, the radiance leaving the fibre per unit of irradiance (on a
// plane facing the light) arriving as a narrow beam: for a directional light of irradiance E,
// L_o = E · S(ω_i, ω_o), the BCSDF times cos θ_i.
#include <array>
#include <limits>
#include <memory>
#include <vector>

#include "core/math.hpp"

namespace wisp {

// Absorption σa (per unit of fibre radius) of eumelanin and pheomelanin at unit concentration:
// Chiang et al. 2016 §4.1 (after d'Eon et al. 2011), as pbrt-v4 uses them.
Vec3f eumelanin_absorption();
Vec3f pheomelanin_absorption();

struct Melanin {
    float eumelanin = 0.f;    // concentration, ≥ 0: 0 white … about 8 black
    float pheomelanin = 0.f;  // concentration, ≥ 0: the red of auburn and ginger hair
};

Vec3f melanin_absorption(const Melanin& m);

// The σa whose fibres give hair of colour `c` (linear RGB, each in (0, 1]) once light has
// scattered through many of them: Chiang et al. 2016 eq. 9, a fit over their path-traced
// hair for azimuthal roughness β_n.
Vec3f absorption_from_color(const Vec3f& c, float beta_n);

// The colour of hair whose fibres absorb σa: eq. 9 the other way, c = e^(−k(β_n)·√σa).
Vec3f color_from_absorption(const Vec3f& sigma_a, float beta_n);

// The melanin concentrations whose hair looks nearest colour `c` (linear RGB, by eq. 9): the
// share of pheomelanin that gives c's balance of red to green (the nearer pigment alone where
// none does), and the amount that gives c's luminance (Rec. 709).
// Hair takes its colour from two pigments only, and both absorb blue most, so a neutral grey
// or black comes out as the brown of its lightness, as real dark hair is.
Melanin melanin_from_color(const Vec3f& c, float beta_n);

struct FiberParams {
    float eta = 1.55f;    // refractive index of keratin
    float beta_m = 0.3f;  // longitudinal roughness, in [0.01, 1] (Cycles' "Roughness")
    float beta_n = 0.3f;  // azimuthal roughness, in [0.01, 1] (Cycles' "Radial Roughness")
    float alpha = 2.f;    // cuticle tilt toward the tip, degrees, in [−10, 10] (Cycles' "Offset")
    // Dual scattering's density factors (Zinke et al. 2008 §4.3): how much of the light the
    // fibres around a point scatter back (d_b) and pass forward (d_f), for hair that is not a
    // tight bundle. 0.7 in the paper.
    float back_density = 0.7f;
    float forward_density = 0.7f;
};

// The per-render tables of one set of FiberParams.
class FiberScattering {
  public:
    explicit FiberScattering(const FiberParams& params = {});

    // What evaluating for one eye direction shares between lights.
    struct View {
        Vec3f t;      // unit tangent, root to tip
        float sin_o;  // t·ω_o
        float cos_o;
        float theta_o;  // asin(sin_o)
        Vec3f op;       // ω_o's projection on the plane normal to t
        float op2;      // its squared length
        int row = 0;    // the |sin θ_o| row of the azimuthal tables, and its weight
        float row_w = 0;
        int m_col = 0;  // the sin θ_o column of the longitudinal tables, and its weight
        float m_col_w = 0;
    };
    View view(const Vec3f& tangent, const Vec3f& to_eye) const;

    // S(ω_i, ω_o) for unit ω_i (toward the light), a strand of absorption σa.
    Vec3f eval(const View& v, const Vec3f& to_light, const Vec3f& sigma_a) const;
    Vec3f eval(const Vec3f& tangent, const Vec3f& to_light, const Vec3f& to_eye,
               const Vec3f& sigma_a) const {
        return eval(view(tangent, to_eye), to_light, sigma_a);
    }

    // A fibre's albedos for light that reaches it from all around (Zinke et al. 2008's ā_f and
    // ā_b): the share it sends on forward (the half-space of azimuths away from the light)
    // and back, and the dual-scattering back-scatter A_b of the fibres behind it.
    struct Albedo {
        Vec3f forward = Vec3f::Zero(), backward = Vec3f::Zero();
        Vec3f log_forward = Vec3f::Zero();  // ln ā_f, for ā_f^n
        // A_b = ā_b ā_f² / (1 − ā_f²) + ā_b³ ā_f² / (1 − ā_f²)³
        Vec3f back_scatter = Vec3f::Zero();
    };
    Albedo albedo(const Vec3f& sigma_a) const;

    // Light scattered more than once in the hair (dual scattering, Zinke et al. 2008, "Dual
    // Scattering Approximation for Fast Multiple Scattering in Hair", §4): arriving through
    // `fibres` fibres between the light and the point, most of it scattered forward by them,
    // tinted by ā_f at each and spread in θ, then sent back toward the eye by the fibres
    // around the point. Per steradian and unit irradiance, as eval; without the light that
    // arrives unscattered (eval × e^−fibres).
    // `behind`: the fibres behind the point along the light, whose back-scattering A_b sums:
    // Zinke's A_b is for hair as deep as the light goes, which light hair (ā_f near 1, so
    // the sum over layers converges slowly) is not on a head; A_b over m layers is taken as
    // A_b · (1 − ā_f^2m), its first term's share exactly.
    Vec3f multiple(const View& v, const Vec3f& to_light, const Albedo& a, float fibres,
                   float behind = std::numeric_limits<float>::infinity()) const;

    // Table sizes: azimuth φ ∈ [0, π] and |sin θ_o| ∈ [0, 1] for N̄ and L̄; sin θ_i and sin θ_o
    // ∈ [−1, 1] for M.
    static constexpr int kPhi = 96, kThetaO = 32, kM = 128;

  private:
    FiberParams params_;
    // sin and cos of the shift of θ_i for R (+2α), TT (−α) and TRT (−4α).
    float tilt_sin_[3], tilt_cos_[3];
    // #2·kThetaO·kPhi: at (row, φ column) two sets of four, (N̄_R, N̄_TT, N̄_TRT, L̄_TT) and
    // (L̄_TRT, and the row's rest p ≥ 3 without absorption, its mean Fresnel factor f̄ and its
    // mean path l̄ through the fibre: A_3 ≈ F̄₃ · T³ (1 − f̄) / (1 − f̄ T), T = e^−σa·l̄),
    // interpolated together.
    std::vector<Eigen::Array4f> azimuthal_;
    // #3·kM·kM: M_p at (p, sin θ_i row, sin θ_o column).
    std::vector<float> m_;
    // For albedo(), at θ_o = 0: per path p, the share of N̄_p sent forward and back, and the
    // mean path inside the fibre of each.
    float forward_[3], backward_[3], forward_path_[3], backward_path_[3];
    // For multiple(): the longitudinal variances of back-scattering (R and TRT) and of one
    // fibre's forward scattering (TT).
    float back_variance_ = 0, forward_variance_ = 0;
};

// The tables for `params`, shared: built once for the parameters last asked for (about 50 ms),
// which a contact sheet's views and an editor's successive renders ask for again.
std::shared_ptr<const FiberScattering> fiber_scattering(const FiberParams& params);

}  // namespace wisp

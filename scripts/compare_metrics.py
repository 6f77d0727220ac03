#!/usr/bin/env python3
# Measures how close wisp's pictures are to Cycles' on the same strands, camera and lights:
# the hair's mean colour, its saturation and its contrast between lit and shaded strands,
# for the pictures scripts/compare_blender --colors leaves in OUT_DIR. numpy only (PNG
# decoding with zlib, CIELAB and CIEDE2000 written out here), so it runs wherever the
# comparison does.
#   scripts/compare_metrics.py OUT_DIR COLOUR... [--shading NAME]
#   scripts/compare_metrics.py --self-test
# For each COLOUR it reads, from OUT_DIR:
#   COLOUR_wisp.png                    wisp's picture (wisp's grey background)
#   COLOUR_wisp_hair_black.png         wisp's picture of the hair alone (the head replaced by
#   COLOUR_wisp_hair_white.png         a speck) over a black and over a white background
#   COLOUR_wisp.json                   {"render_seconds": wisp's wall time}
#   COLOUR_cycles.png                  Cycles' picture
#   COLOUR_cycles_hair.npy             Cycles' hair coverage per pixel (blender_hair.py
#                                      --coverage)
#   COLOUR_cycles.json                 blender_hair.py --stats
# and writes COLOUR_mask.png (the pixels measured, white) and OUT_DIR/table.md, which it
# also prints.
#
# The mask. A pixel is measured when hair covers it (nearly) entirely in both pictures:
#   wisp:   coverage 1 − mean over RGB of (white − black) of the hair-alone pictures, in
#           linear RGB: wisp composites in linear light, so a pixel the hair covers by α
#           differs by (1 − α) between a black and a white background;
#   Cycles: the fraction of the pixel's camera samples whose first hit is a strand;
# both ≥ COVERAGE_MIN. Cycles' coverage is the hair in front of the head, so the
# intersection leaves out the skin (the head is the same mesh seen by the same camera in
# both), the background, and the thin ends where either picture mixes hair with what is
# behind it, which would measure the skin's and the background's colour as much as the
# hair's. wisp's own coverage is taken without the head since wisp has no pass that tells
# hair from skin; where the head hides hair, Cycles' coverage is 0 and drops the pixel.
import argparse
import json
import os
import struct
import sys
import zlib

import numpy as np

COVERAGE_MIN = 0.95
LIT_SHADOW_FRACTION = 0.2  # the brightest and the darkest 20 % of the hair pixels


# ---- PNG ------------------------------------------------------------------------------


def read_png(path):
    """An 8- or 16-bit, non-interlaced grey, grey+alpha, RGB or RGBA PNG as an #H×#W×C
    float array in [0, 1] (the stored, sRGB-encoded values)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    at, idat, header = 8, [], None
    while at < len(data):
        length, kind = struct.unpack_from(">I4s", data, at)
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        at += 12 + length
    width, height, depth, color_type, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(color_type)
    if channels is None or depth not in (8, 16) or interlace:
        raise ValueError(f"{path}: unsupported PNG (colour type {color_type}, depth {depth}, "
                         f"interlace {interlace})")
    bpp = channels * depth // 8  # bytes per pixel, the filters' unit
    stride = width * bpp
    raw = np.frombuffer(zlib.decompress(b"".join(idat)), np.uint8).reshape(height, stride + 1)
    out = np.zeros((height, stride), np.uint8)
    prior = np.zeros(stride, np.int32)
    for y in range(height):
        kind, row = raw[y, 0], raw[y, 1:].astype(np.int32)
        if kind == 0:
            rec = row
        elif kind == 1:  # Sub: a running sum along the row, per byte of the pixel
            rec = np.cumsum(row.reshape(-1, bpp), axis=0).ravel() & 255
        elif kind == 2:  # Up
            rec = (row + prior) & 255
        elif kind in (3, 4):  # Average and Paeth depend on the byte just reconstructed
            rec = row.tolist()
            up = prior.tolist()
            for x in range(stride):
                left = rec[x - bpp] if x >= bpp else 0
                if kind == 3:
                    rec[x] = (rec[x] + ((left + up[x]) >> 1)) & 255
                else:
                    ul = up[x - bpp] if x >= bpp else 0
                    p = left + up[x] - ul
                    pa, pb, pc = abs(p - left), abs(p - up[x]), abs(p - ul)
                    pred = left if pa <= pb and pa <= pc else (up[x] if pb <= pc else ul)
                    rec[x] = (rec[x] + pred) & 255
            rec = np.array(rec, np.int32)
        else:
            raise ValueError(f"{path}: row {y}: unknown filter {kind}")
        out[y] = rec
        prior = rec
    if depth == 16:
        px = out.reshape(height, width * channels, 2).astype(np.uint16)
        return ((px[..., 0] << 8) | px[..., 1]).reshape(height, width, channels) / 65535.0
    return out.reshape(height, width, channels) / 255.0


def write_png(path, gray):
    """An #H×#W array in [0, 1] as an 8-bit grey PNG."""
    g = np.clip(np.round(np.asarray(gray) * 255), 0, 255).astype(np.uint8)
    raw = b"".join(b"\0" + row.tobytes() for row in g)

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n"
                + chunk(b"IHDR", struct.pack(">IIBBBBB", g.shape[1], g.shape[0], 8, 0, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


# ---- Colour ---------------------------------------------------------------------------


def srgb_to_linear(v):
    v = np.asarray(v, np.float64)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(v):
    v = np.clip(np.asarray(v, np.float64), 0, 1)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def relative_luminance(linear_rgb):
    return np.asarray(linear_rgb) @ np.array([0.2126, 0.7152, 0.0722])


def linear_to_lab(linear_rgb):
    """Linear sRGB (…×3) → CIELAB (D65 white)."""
    m = np.array([[0.4124564, 0.3575761, 0.1804375],
                  [0.2126729, 0.7151522, 0.0721750],
                  [0.0193339, 0.1191920, 0.9503041]])
    xyz = np.asarray(linear_rgb, np.float64) @ m.T / np.array([0.95047, 1.0, 1.08883])
    d = 6 / 29
    f = np.where(xyz > d ** 3, np.cbrt(xyz), xyz / (3 * d * d) + 4 / 29)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]),
                     200 * (f[..., 1] - f[..., 2])], axis=-1)


def hsv_saturation(srgb):
    """HSV S of sRGB-encoded values (…×3): (max − min) / max, 0 for black."""
    hi, lo = srgb.max(axis=-1), srgb.min(axis=-1)
    return np.divide(hi - lo, hi, out=np.zeros_like(hi), where=hi > 0)


def ciede2000(lab1, lab2):
    """CIEDE2000 colour difference (Sharma, Wu and Dalal 2005) with k_L = k_C = k_H = 1."""
    L1, a1, b1 = np.moveaxis(np.asarray(lab1, np.float64), -1, 0)
    L2, a2, b2 = np.moveaxis(np.asarray(lab2, np.float64), -1, 0)
    c_bar = (np.hypot(a1, b1) + np.hypot(a2, b2)) / 2
    g = 0.5 * (1 - np.sqrt(c_bar ** 7 / (c_bar ** 7 + 25.0 ** 7)))
    a1p, a2p = (1 + g) * a1, (1 + g) * a2
    c1p, c2p = np.hypot(a1p, b1), np.hypot(a2p, b2)
    # Hue angles in degrees, 0 for a neutral colour (a' = b = 0).
    h1p = np.where((a1p == 0) & (b1 == 0), 0.0, np.degrees(np.arctan2(b1, a1p)) % 360)
    h2p = np.where((a2p == 0) & (b2 == 0), 0.0, np.degrees(np.arctan2(b2, a2p)) % 360)
    neutral = c1p * c2p == 0
    # Hues exactly opposite (Sharma's pair 14) count as |Δh| ≤ 180, as the paper has it; the
    # arctangents round their difference either side of 180, hence the slack.
    slack = 1e-9
    dh = h2p - h1p
    dh = np.where(dh > 180 + slack, dh - 360, np.where(dh < -180 - slack, dh + 360, dh))
    dh = np.where(neutral, 0.0, dh)
    d_lp, d_cp = L2 - L1, c2p - c1p
    d_hp = 2 * np.sqrt(c1p * c2p) * np.sin(np.radians(dh / 2))
    l_bar, c_bar_p = (L1 + L2) / 2, (c1p + c2p) / 2
    h_sum = h1p + h2p
    h_bar = np.where(neutral, h_sum,
                     np.where(np.abs(h1p - h2p) <= 180 + slack, h_sum / 2,
                              np.where(h_sum < 360, (h_sum + 360) / 2, (h_sum - 360) / 2)))
    t = (1 - 0.17 * np.cos(np.radians(h_bar - 30)) + 0.24 * np.cos(np.radians(2 * h_bar))
         + 0.32 * np.cos(np.radians(3 * h_bar + 6)) - 0.20 * np.cos(np.radians(4 * h_bar - 63)))
    d_theta = 30 * np.exp(-(((h_bar - 275) / 25) ** 2))
    r_c = 2 * np.sqrt(c_bar_p ** 7 / (c_bar_p ** 7 + 25.0 ** 7))
    s_l = 1 + 0.015 * (l_bar - 50) ** 2 / np.sqrt(20 + (l_bar - 50) ** 2)
    s_c = 1 + 0.045 * c_bar_p
    s_h = 1 + 0.015 * c_bar_p * t
    r_t = -np.sin(np.radians(2 * d_theta)) * r_c
    return np.sqrt((d_lp / s_l) ** 2 + (d_cp / s_c) ** 2 + (d_hp / s_h) ** 2
                   + r_t * (d_cp / s_c) * (d_hp / s_h))


# Sharma, Wu and Dalal 2005, Table 1: L1 a1 b1 L2 a2 b2 ΔE00, the pairs that exercise the
# hue's wrap-around, the neutral axis and the blue region's rotation term.
SHARMA_PAIRS = np.array([
    [50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425],
    [50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615],
    [50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412],
    [50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000],
    [50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000],
    [50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000],
    [50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669],
    [50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669],
    [50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792],
    [50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792],
    [50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195],
    [50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195],
    [50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045],
    [50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045],
    [50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461],
    [50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065],
    [50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492],
    [50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977],
    [50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030],
    [50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535],
    [50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000],
    [50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000],
    [50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000],
    [50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000],
    [60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644],
    [63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630],
    [61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731],
    [35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645],
    [22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373],
    [36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146],
    [90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441],
    [90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381],
    [6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377],
    [2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082],
])


def self_test():
    """Checks ciede2000 against Sharma et al.'s 34 pairs (both orders: the formula is
    symmetric) and the colour conversions against known values; raises on a mismatch."""
    for lab1, lab2 in ((SHARMA_PAIRS[:, 0:3], SHARMA_PAIRS[:, 3:6]),
                       (SHARMA_PAIRS[:, 3:6], SHARMA_PAIRS[:, 0:3])):
        got = ciede2000(lab1, lab2)
        bad = np.flatnonzero(np.abs(got - SHARMA_PAIRS[:, 6]) > 5e-5)
        if len(bad):
            i = bad[0]
            raise AssertionError(f"CIEDE2000 pair {i + 1}: got {got[i]:.4f}, "
                                 f"expected {SHARMA_PAIRS[i, 6]:.4f}")
    white = linear_to_lab(np.ones(3))
    assert np.allclose(white, [100, 0, 0], atol=1e-3), white
    red = linear_to_lab(np.array([1.0, 0, 0]))  # sRGB red: L 53.24, a 80.09, b 67.20
    assert np.allclose(red, [53.24, 80.09, 67.20], atol=0.02), red
    v = np.linspace(0, 1, 11)
    assert np.allclose(linear_to_srgb(srgb_to_linear(v)), v)
    return len(SHARMA_PAIRS)


# ---- Measures -------------------------------------------------------------------------


def wisp_coverage(black_png, white_png):
    """wisp's hair coverage per pixel from its pictures over black and over white."""
    black = srgb_to_linear(read_png(black_png)[..., :3])
    white = srgb_to_linear(read_png(white_png)[..., :3])
    return np.clip(1 - (white - black).mean(axis=-1), 0, 1)


def lit_shadow(y):
    """Mean of the brightest LIT_SHADOW_FRACTION of the values over that of the darkest."""
    y = np.sort(np.ravel(y))
    k = max(1, int(round(LIT_SHADOW_FRACTION * len(y))))
    return float(y[-k:].mean() / max(y[:k].mean(), 1e-9))


def measure(srgb, mask):
    """The hair's figures over the masked pixels of an sRGB picture (#H×#W×3 in [0, 1])."""
    px = srgb[mask]
    lin = srgb_to_linear(px)
    mean_lin = lin.mean(axis=0)
    # The same contrast over 4×4 blocks wholly inside the mask: single strands and Cycles'
    # sampling noise (64 samples leave bright and dark speckles) widen the per-pixel
    # spread; the blocks keep the lit and shaded sides of the hair.
    y = relative_luminance(srgb_to_linear(srgb))
    h, w = (mask.shape[0] // 4) * 4, (mask.shape[1] // 4) * 4
    blocks = lambda a: a[:h, :w].reshape(h // 4, 4, w // 4, 4)
    whole = blocks(mask).all(axis=(1, 3))
    y_blocks = blocks(y).mean(axis=(1, 3))[whole]
    return {
        "mean_srgb": linear_to_srgb(mean_lin) * 255,  # the mean of the light, encoded
        "mean_lab": linear_to_lab(mean_lin),
        "saturation": float(hsv_saturation(px).mean()),
        "lit_shadow": lit_shadow(relative_luminance(lin)),
        "lit_shadow_4x4": lit_shadow(y_blocks) if len(y_blocks) else float("nan"),
        "blocks_4x4": int(len(y_blocks)),
    }


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except OSError:
        return {}


def compare(out_dir, colour):
    p = lambda suffix: os.path.join(out_dir, f"{colour}_{suffix}")
    wisp_pic = read_png(p("wisp.png"))[..., :3]
    cycles_pic = read_png(p("cycles.png"))[..., :3]
    cov_w = wisp_coverage(p("wisp_hair_black.png"), p("wisp_hair_white.png"))
    cov_c = np.load(p("cycles_hair.npy"))
    if cov_w.shape != cov_c.shape or wisp_pic.shape != cycles_pic.shape:
        raise ValueError(f"{colour}: the pictures differ in size")
    mask = (cov_w >= COVERAGE_MIN) & (cov_c >= COVERAGE_MIN)
    write_png(p("mask.png"), mask.astype(float))
    if mask.sum() < 100:
        raise ValueError(f"{colour}: only {int(mask.sum())} pixels are hair in both pictures")
    w, c = measure(wisp_pic, mask), measure(cycles_pic, mask)
    cycles_stats = load_json(p("cycles.json"))
    return {
        "colour": colour, "pixels": int(mask.sum()),
        "wisp_hair_pixels": int((cov_w >= COVERAGE_MIN).sum()),
        "cycles_hair_pixels": int((cov_c >= COVERAGE_MIN).sum()),
        "wisp": w, "cycles": c,
        "de2000": float(ciede2000(w["mean_lab"], c["mean_lab"])),
        "saturation_diff": w["saturation"] / c["saturation"] - 1,
        "lit_shadow_diff": w["lit_shadow"] / c["lit_shadow"] - 1,
        "lit_shadow_4x4_diff": w["lit_shadow_4x4"] / c["lit_shadow_4x4"] - 1,
        "wisp_seconds": load_json(p("wisp.json")).get("render_seconds"),
        "cycles_seconds": cycles_stats.get("render_seconds"),
        "melanin": cycles_stats.get("melanin", {}),
    }


def table(rows, shading):
    def rgb(v):
        return ", ".join(f"{x:.0f}" for x in v)

    def lab(v):
        return f"{v[0]:.1f}, {v[1]:.1f}, {v[2]:.1f}"

    def secs(v):
        return "–" if v is None else f"{v:.1f}"

    look = "its default shading" if shading == "default" else f"`--shading {shading}`"
    lines = [
        f"wisp ({look}) against Cycles' Principled Hair BSDF (melanin) over the pixels both "
        f"cover with hair (coverage ≥ {COVERAGE_MIN}). Mean colour: the mean of the linear "
        "light, sRGB-encoded (0–255) and in CIELAB (D65); S: mean HSV saturation of the "
        f"pixels; lit/shadow: mean luminance of the brightest {LIT_SHADOW_FRACTION:.0%} of "
        f"the pixels over the darkest {LIT_SHADOW_FRACTION:.0%}; Δ: wisp / Cycles − 1; "
        "times: wisp's wall time, Cycles' render (scene sync included, import not).",
        "",
        "| colour | pixels | wisp sRGB | Cycles sRGB | wisp L\\*a\\*b\\* | Cycles L\\*a\\*b\\* "
        "| ΔE00 | S wisp | S Cycles | ΔS | lit/shadow wisp | lit/shadow Cycles "
        "| Δ lit/shadow | wisp s | Cycles s |",
        "| --- | ---: | --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: "
        "| ---: | ---: |",
    ]
    for r in rows:
        w, c = r["wisp"], r["cycles"]
        lines.append(
            f"| {r['colour']} | {r['pixels']} | {rgb(w['mean_srgb'])} | {rgb(c['mean_srgb'])} "
            f"| {lab(w['mean_lab'])} | {lab(c['mean_lab'])} | {r['de2000']:.1f} "
            f"| {w['saturation']:.2f} | {c['saturation']:.2f} | {r['saturation_diff']:+.0%} "
            f"| {w['lit_shadow']:.1f} | {c['lit_shadow']:.1f} | {r['lit_shadow_diff']:+.0%} "
            f"| {secs(r['wisp_seconds'])} | {secs(r['cycles_seconds'])} |")
    lines += [
        "",
        "The inputs and a smoother contrast. Strand colour: the mean of the strands' linear "
        "colours, sRGB-encoded; melanin colour: the colour Chiang et al.'s eq. 9 gives back "
        "for the melanin fitted to each strand (what two pigments can make of it); m, r: "
        "Cycles' mean Melanin and Melanin Redness; lit/shadow 4×4: the contrast over 4×4-pixel "
        "blocks wholly in the mask (fewer single strands and less of Cycles' noise).",
        "",
        "| colour | strand colour | melanin colour | m | r | blocks | lit/shadow 4×4 wisp "
        "| lit/shadow 4×4 Cycles | Δ |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for r in rows:
        mel, w, c = r["melanin"], r["wisp"], r["cycles"]
        strand = rgb(linear_to_srgb(mel["mean_color_linear"]) * 255) if mel else "–"
        fitted = (rgb(linear_to_srgb(mel["mean_fitted_color_linear"]) * 255)
                  if "mean_fitted_color_linear" in mel else "–")
        m_r = f"{mel['melanin_mean']:.3f} | {mel['redness_mean']:.3f}" if mel else "– | –"
        lines.append(
            f"| {r['colour']} | {strand} | {fitted} | {m_r} | {w['blocks_4x4']} "
            f"| {w['lit_shadow_4x4']:.1f} | {c['lit_shadow_4x4']:.1f} "
            f"| {r['lit_shadow_4x4_diff']:+.0%} |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("out_dir", nargs="?")
    ap.add_argument("colours", nargs="*")
    ap.add_argument("--shading", default="default", help="wisp's --shading, for the caption")
    ap.add_argument("--self-test", action="store_true", help="only run the self-test")
    a = ap.parse_args()
    n = self_test()
    if a.self_test:
        print(f"compare_metrics: self-test passed (CIEDE2000 on Sharma et al.'s {n} pairs)")
        return 0
    if not a.out_dir or not a.colours:
        ap.error("give OUT_DIR and at least one colour")
    rows = [compare(a.out_dir, c) for c in a.colours]
    text = table(rows, a.shading)
    with open(os.path.join(a.out_dir, "table.md"), "w") as f:
        f.write(text)
    with open(os.path.join(a.out_dir, "metrics.json"), "w") as f:
        json.dump(rows, f, indent=1, default=lambda v: v.tolist())
    print(text, end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())

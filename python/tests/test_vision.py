"""Decode, scan and sphere fitting against the ramtk command on the same set, the simulator's
truth and closed forms; numpy arrays share the C++ buffers."""
import json
import os
import pathlib

import numpy as np
import pytest

import ramtk


@pytest.fixture(scope="module")
def default_set(datasets):
    return datasets / "scan_default" / "manifest.json"


def test_decode_matches_the_command_and_shares_memory(cli, default_set, scratch):
    out = scratch / "decode_cli"
    cli("decode", default_set, "--camera", "left", "--out", out, "--force")
    expected = json.loads((out / "left_summary.json").read_text())
    d = ramtk.decode(str(default_set), "left")
    for key in ("valid_fraction", "median_modulation_dn", "median_sigma_phase_rad", "fit_residual_rms_dn"):
        assert d.summary[key] == pytest.approx(expected[key], rel=1e-12), key
    c = d.coordinate
    assert c.dtype == np.float32 and c.shape == (512, 640)
    # Zero copy: the array does not own its data; it views the C++ matrix.
    assert not c.flags["OWNDATA"] and c.base is not None
    valid = d.mask == 255
    assert np.isfinite(c[valid]).all() and np.isnan(c[~valid]).all()
    assert valid.mean() == pytest.approx(expected["valid_fraction"], abs=1e-12)


def test_decode_noise_split_and_the_old_rule(default_set):
    # The default set is rendered without projector harmonics: the random part of the residual is
    # the whole residual (to the estimate's own ~1 % error), and whole_residual_sigma=True gives
    # the whole residual by definition.
    d = ramtk.decode(str(default_set), "left").summary
    assert d["sigma_intensity_random_dn"] == pytest.approx(d["fit_residual_rms_dn"], rel=0.03)
    assert d["sigma_intensity_dn"] == d["sigma_intensity_random_dn"]
    old = ramtk.decode(str(default_set), "left", whole_residual_sigma=True).summary
    assert old["sigma_intensity_dn"] == old["fit_residual_rms_dn"]
    assert old["phase_ripple_rad"] == 0


def test_scan_matches_the_command_and_the_truth(cli, default_set, scratch, datasets):
    out = scratch / "scan_cli"
    cli("scan", default_set, "--out", out, "--force")
    expected = json.loads((out / "spheres.json").read_text())
    r = ramtk.scan(str(default_set))
    assert r.cloud.points_mm.shape[1] == 3
    assert len(r.cloud) == r.summary["points"]
    s = r.spheres[0]
    centre_cli = expected["spheres"][0]["centre_mm"]
    np.testing.assert_allclose(s.centre_mm, centre_cli, atol=1e-9)
    # The Cramér–Rao bound is in spheres.json, the library's value, and no larger than the fit's σ
    # (the fit's σ also carries the residuals' variance factor, ~1 here).
    np.testing.assert_allclose(s.crlb_centre_sigma_mm, expected["spheres"][0]["crlb_centre_sigma_mm"], rtol=1e-9)
    assert s.crlb_radius_sigma_mm == pytest.approx(expected["spheres"][0]["crlb_radius_sigma_mm"], rel=1e-9)
    assert (s.crlb_centre_sigma_mm > 0).all()
    assert (s.crlb_centre_sigma_mm < 1.5 * s.centre_sigma_mm).all()
    # Against the simulator's truth: within 5 predicted standard deviations per axis.
    truth = ramtk.read_truth_spheres(str(datasets / "scan_default" / "truth" / "truth.json"))[0]
    sigma = s.centre_sigma_mm
    assert (np.abs(s.centre_mm - truth.centre_mm) < 5 * sigma + 1e-4).all()


def test_scan_in_a_window_finds_the_same_ball(default_set):
    full = ramtk.scan(str(default_set))
    win = ramtk.scan(str(default_set), roi="auto")
    assert win.summary["roi"]["source"].startswith("auto (coarse pass, stride 2)")
    x, y, w, h = win.summary["roi"]["left"]
    assert w < 640 and h < 512
    assert len(win.cloud) < len(full.cloud)
    # The same pixels on the ball decode and match as in the whole frame: the centres agree far
    # inside the centre's own sigma (same images, same noise).
    sigma = full.spheres[0].centre_sigma_mm
    assert (np.abs(win.spheres[0].centre_mm - full.spheres[0].centre_mm) < 0.3 * sigma).all()
    with pytest.raises(Exception, match="--roi"):
        ramtk.scan(str(default_set), roi="nowhere")


def test_scan_second_order_options_match_the_command(cli, default_set, scratch):
    # noise_term=False and kernel_estimate="auto" are `ramtk scan --no-noise-term` and
    # `--kernel-estimate auto`: the same centres as the command's spheres.json.
    for flags, kwargs in (((" --no-noise-term",), {"noise_term": False}),
                          ((" --kernel-estimate", "auto"), {"kernel_estimate": "auto"})):
        out = scratch / ("scan_cli_" + "_".join(f.strip("- ") for f in flags))
        cli("scan", default_set, "--out", out, "--force", *[f.strip() for f in flags])
        expected = json.loads((out / "spheres.json").read_text())["spheres"][0]["centre_mm"]
        np.testing.assert_allclose(ramtk.scan(str(default_set), **kwargs).spheres[0].centre_mm, expected, atol=1e-9)
    with pytest.raises(Exception, match="kernel_estimate"):
        ramtk.scan(str(default_set), kernel_estimate="maybe")


def test_fit_sphere_recovers_a_noisy_sphere():
    rng = np.random.default_rng(7)
    centre, radius, noise = np.array([10.0, -20.0, 700.0]), 19.05, 0.005
    # A cap seen from the origin (the front half), as a camera sees a ball.
    v = rng.normal(size=(6000, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    v = v[v[:, 2] < 0]
    points = centre + radius * v + rng.normal(scale=noise, size=v.shape)
    fits = ramtk.fit_sphere(points, radius=radius)
    assert len(fits) == 1
    f = fits[0]
    sigma = f.centre_sigma_mm
    # Closed-form scale of the centre sigma for N points on a hemisphere: ~ noise * sqrt(3/N) per axis.
    assert (sigma < 10 * noise * np.sqrt(3 / len(points))).all()
    assert (np.abs(f.centre_mm - centre) < 5 * sigma).all()
    assert f.radius_mm == pytest.approx(radius, abs=5 * f.radius_sigma_mm + 1e-6)
    assert f.rms_mm == pytest.approx(noise, rel=0.1)


def test_fit_sphere_rejects_bad_shapes():
    with pytest.raises(ramtk.InputError) as e:
        ramtk.fit_sphere(np.zeros((10, 2)))
    assert e.value.field == "points"
    with pytest.raises(ramtk.InputError):
        ramtk.fit_sphere(np.zeros((10, 3)), sigma=np.ones(3))


def test_stereo_calibration_round_trip(datasets, scratch):
    c = ramtk.StereoCalibration.read(str(datasets / "scan_default" / "calibration.yml"))
    assert c.left_K[0, 0] == pytest.approx(4700.0)  # the file's value
    assert c.image_size == (640, 512)
    r = c.right_from_left[:3, :3]
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-9)
    for name in ("copy.yml", "copy.json"):
        c.write(str(scratch / name))
        d = ramtk.StereoCalibration.read(str(scratch / name))
        np.testing.assert_allclose(d.left_K, c.left_K, rtol=1e-12)
        np.testing.assert_allclose(d.right_from_left, c.right_from_left, rtol=1e-12, atol=1e-12)


def test_keyword_defaults_are_the_command_defaults():
    # The signatures carry the command line's names and defaults (ramtk scan --help), readable by
    # inspect (and so by help() and editors).
    import inspect

    p = inspect.signature(ramtk.scan).parameters
    assert p["radius"].default == 19.05 and p["min_depth"].default == 100.0 and p["max_depth"].default == 10000.0
    assert p["roi"].default == "full" and p["phase_filter"].default == 0 and p["spheres"].default == 1
    assert inspect.signature(ramtk.decode).parameters["min_modulation"].default == 0.02


def test_manifest_reader(default_set):
    m = ramtk.read_manifest(str(default_set))
    assert len(m["resolved_images"]["left"]) == 19
    assert all(pathlib.Path(p).exists() for p in m["resolved_images"]["right"])
    assert m["sequence"][0]["type"] == "phase_shift"


def test_bad_manifest_names_the_file(scratch):
    bad = scratch / "bad_manifest.json"
    bad.write_text('{"projector": {"width": 0, "height": 10}}')
    with pytest.raises(ramtk.InputError) as e:
        ramtk.decode(str(bad))
    assert e.value.file == str(bad)


def test_windowed_scan_of_bmp_frames_reads_their_rows(scratch):
    # The same rendered set written as PNG and as BMP: the windowed scan reads only the BMPs' rows
    # it needs, and finds the same ball from the same samples.
    png = ramtk.simulate_fringe(str(scratch / "png"), seed=3, supersampling=1, force=True)
    bmp = ramtk.simulate_fringe(str(scratch / "bmp"), seed=3, supersampling=1, force=True, frame_format="bmp")
    a = ramtk.scan(png.manifest, roi="auto")
    b = ramtk.scan(bmp.manifest, roi="auto")
    assert a.summary["roi"]["frame_reads"] == "whole"
    assert b.summary["roi"]["frame_reads"] == "rows"
    assert (a.cloud.points_mm == b.cloud.points_mm).all()
    assert (a.spheres[0].centre_mm == b.spheres[0].centre_mm).all()
    with pytest.raises(Exception, match="frame_format"):
        ramtk.simulate_fringe(str(scratch / "tiff"), frame_format="tiff")


def test_simulated_phase_origin_and_truth_maps(ramtk_binary, scratch):
    # `simulate fringe --phase-at-origin 0` writes that origin into the manifest, and the decoded
    # coordinate matches the simulator's true projector_x map (read back with read_image).
    import subprocess

    out = scratch / "origin0"
    subprocess.run([ramtk_binary, "simulate", "fringe", "--out", str(out), "--seed", "2", "--phase-at-origin", "0",
                    "--no-noise", "--force", "-q"], check=True, capture_output=True)
    m = ramtk.read_manifest(str(out / "manifest.json"))
    assert m["sequence"][0]["phase_at_origin_deg"] == 0
    d = ramtk.decode(str(out / "manifest.json"), "left")
    truth = ramtk.read_image(str(out / "truth" / "left_projector_x.tif"))
    lit = ramtk.read_image(str(out / "truth" / "left_lit_fraction.tif"))
    assert truth.dtype == np.float32 and truth.shape == d.coordinate.shape
    ok = np.isfinite(d.coordinate) & np.isfinite(truth) & (lit > 0.999)
    assert ok.sum() > 100000
    # Noise-free, 8-bit: the quantisation step q = 1/255 of full scale gives a phase error of about
    # sqrt(2/N)·(q/√12)/B ≈ 0.0012 rad at B ≈ 0.4 of full scale (N = 12), i.e. 0.004 px of a 20 px
    # period. RMS within 2.5× that, and no bias beyond 0.001 px.
    e = d.coordinate[ok] - truth[ok]
    assert np.sqrt(np.mean(e.astype(np.float64) ** 2)) < 0.01
    assert abs(float(np.mean(e))) < 0.001


def test_read_image_refuses_fifos_and_devices(scratch):
    """A FIFO would block imread forever and /dev/zero never ends: refused before opening."""
    folder = scratch / "special_images"
    folder.mkdir(exist_ok=True)
    fifo = folder / "frame.png"
    if not fifo.exists():
        os.mkfifo(fifo)
    zero = folder / "zero.png"
    if not zero.exists():
        zero.symlink_to("/dev/zero")
    for path, what in ((fifo, "FIFO"), (zero, "character device")):
        with pytest.raises(ramtk.InputError) as e:
            ramtk.read_image(str(path))
        assert what in str(e.value) and e.value.file == str(path)

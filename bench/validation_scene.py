#!/usr/bin/env python3
"""A validation scene no default was chosen on, rendered with Cycles (bpy, Blender as a Python module):
every constant of the presets was picked on the four scenes of ../shared/data, so this is a fifth
scene to score them on, held out by construction. Usage (bpy in a venv of its own, as
scripts/test_blender.sh makes one; oiiotool on PATH):

    python -m venv bpy-venv && bpy-venv/bin/pip install bpy
    bpy-venv/bin/python bench/validation_scene.py OUT/dolly [--frames 32] [--levels 4,16,64] [--reference 512]

Unlike the shared scenes: textured albedo on every surface (checker and noise), a camera that dollies
and pans while a torus spins and a box slides across the floor, and two lights (a large area light
and a small warm point light). Renders OUT/render/<level>/frame.####.exr (Blender's multilayer
frames), then writes the shared data's layout beside them: OUT/<level>/indirect.####.exr (Diffuse
Indirect, half, ZIP), OUT/ref/indirect.####.exr, OUT/aux/albedo, normal (R, G, B) and vector
(X, Y, Z, W, float) from the 64-spp render, so bench/quality_targets.py --data OUT/.. scores it.
"""
import argparse
import math
import os
import subprocess

import bpy

RGB = list(zip("RGB", "RGB"))


def material(name, colour_a, colour_b, scale, kind="CHECKER"):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    bsdf = nodes.get("Principled BSDF")
    bsdf.inputs["Roughness"].default_value = 1.0
    tex = nodes.new("ShaderNodeTexChecker" if kind == "CHECKER" else "ShaderNodeTexNoise")
    tex.inputs["Scale"].default_value = scale
    if kind == "CHECKER":
        tex.inputs["Color1"].default_value = (*colour_a, 1)
        tex.inputs["Color2"].default_value = (*colour_b, 1)
        links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    else:
        ramp = nodes.new("ShaderNodeValToRGB")
        ramp.color_ramp.elements[0].color = (*colour_a, 1)
        ramp.color_ramp.elements[1].color = (*colour_b, 1)
        links.new(tex.outputs["Fac"], ramp.inputs["Fac"])
        links.new(ramp.outputs["Color"], bsdf.inputs["Base Color"])
    return m


def plane(name, location, rotation, size, mat):
    bpy.ops.mesh.primitive_plane_add(size=size, location=location, rotation=rotation)
    o = bpy.context.object
    o.name = name
    o.data.materials.append(mat)
    return o


def build(frames):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.use_animated_seed = True
    scene.cycles.max_bounces = 4
    scene.cycles.diffuse_bounces = 3
    scene.cycles.glossy_bounces = 0
    scene.cycles.transmission_bounces = 0
    scene.cycles.sample_clamp_indirect = 0
    scene.render.resolution_x, scene.render.resolution_y = 160, 120
    scene.render.resolution_percentage = 100
    scene.render.use_motion_blur = False
    scene.frame_start, scene.frame_end = 1, frames
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world

    floor = material("floor", (0.7, 0.65, 0.55), (0.25, 0.2, 0.15), 6.0)
    wall = material("wall", (0.75, 0.75, 0.8), (0.35, 0.4, 0.55), 4.0, kind="NOISE")
    side = material("side", (0.7, 0.25, 0.2), (0.5, 0.15, 0.1), 3.0, kind="NOISE")
    other = material("other", (0.2, 0.55, 0.3), (0.15, 0.4, 0.2), 3.0, kind="NOISE")
    plane("floor", (0, 0, 0), (0, 0, 0), 12, floor)
    plane("ceiling", (0, 0, 4), (math.pi, 0, 0), 12, wall)
    plane("back", (0, 4, 2), (math.pi / 2, 0, 0), 12, wall)
    plane("left", (-4, 0, 2), (0, math.pi / 2, 0), 12, side)
    plane("right", (4, 0, 2), (0, -math.pi / 2, 0), 12, other)

    bpy.ops.mesh.primitive_torus_add(location=(-1.2, 1.5, 1.1), major_radius=0.7, minor_radius=0.25)
    torus = bpy.context.object
    torus.data.materials.append(material("torus", (0.9, 0.85, 0.3), (0.6, 0.5, 0.1), 8.0))
    torus.rotation_euler = (0.4, 0, 0)
    torus.keyframe_insert("rotation_euler", frame=1)
    torus.rotation_euler = (0.4, 0, math.pi)
    torus.keyframe_insert("rotation_euler", frame=frames)

    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(-2.0, 0.2, 0.4))
    box = bpy.context.object
    box.data.materials.append(material("box", (0.85, 0.85, 0.85), (0.3, 0.3, 0.35), 5.0))
    box.keyframe_insert("location", frame=1)
    box.location = (2.2, 0.6, 0.4)
    box.keyframe_insert("location", frame=frames)

    bpy.ops.object.light_add(type="AREA", location=(0.5, 1.0, 3.9))
    area = bpy.context.object
    area.data.energy = 400.0
    area.data.size = 1.2
    bpy.ops.object.light_add(type="POINT", location=(2.8, -0.5, 1.5))
    point = bpy.context.object
    point.data.energy = 60.0
    point.data.color = (1.0, 0.75, 0.5)
    point.data.shadow_soft_size = 0.1

    bpy.ops.object.camera_add(location=(1.2, -5.0, 1.8), rotation=(math.radians(80), 0, math.radians(8)))
    camera = bpy.context.object
    scene.camera = camera
    camera.keyframe_insert("location", frame=1)
    camera.keyframe_insert("rotation_euler", frame=1)
    camera.location = (-0.4, -4.2, 1.6)
    camera.rotation_euler = (math.radians(82), 0, math.radians(-6))
    camera.keyframe_insert("location", frame=frames)
    camera.keyframe_insert("rotation_euler", frame=frames)

    layer = scene.view_layers[0]
    layer.use_pass_diffuse_indirect = True
    layer.use_pass_diffuse_color = True
    layer.use_pass_normal = True
    layer.use_pass_vector = True
    scene.render.image_settings.media_type = "MULTI_LAYER_IMAGE"
    scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    scene.render.image_settings.color_depth = "32"
    return scene


def split(out, folder, layer, target, channels, depth):
    """One layer of each multilayer frame of OUT/render/FOLDER as plain files OUT/TARGET.####.exr;
    channels: (name in the file written, channel of the layer) pairs."""
    src_dir = os.path.join(out, "render", folder)
    os.makedirs(os.path.dirname(os.path.join(out, target)), exist_ok=True)
    mapping = ",".join(f"{name}={layer}.{c}" for name, c in channels)
    for name in sorted(os.listdir(src_dir)):
        number = name.split(".")[1]
        subprocess.run(["oiiotool", os.path.join(src_dir, name), "--subimage", layer, "--ch", mapping, "-d", depth,
                        "--compression", "zip", "-o", os.path.join(out, f"{target}.{number}.exr")], check=True)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("out")
    p.add_argument("--frames", type=int, default=32)
    p.add_argument("--levels", default="4,16,64")
    p.add_argument("--reference", type=int, default=512)
    a = p.parse_args()
    scene = build(a.frames)
    runs = [(f"spp{int(s):04d}", int(s)) for s in a.levels.split(",")] + [("ref", a.reference)]
    for folder, samples in runs:
        scene.cycles.samples = samples
        scene.render.filepath = os.path.join(os.path.abspath(a.out), "render", folder, "frame.####")
        bpy.ops.render.render(animation=True)
        split(a.out, folder, "ViewLayer.Diffuse Indirect", f"{folder}/indirect", RGB, "half")
    guides = runs[-2][0]  # the passes of the highest level below the reference
    split(a.out, guides, "ViewLayer.Diffuse Color", "aux/albedo", RGB, "half")
    split(a.out, guides, "ViewLayer.Normal", "aux/normal", list(zip("RGB", "XYZ")), "half")
    split(a.out, guides, "ViewLayer.Vector", "aux/vector", list(zip("XYZW", "XYZW")), "float")


if __name__ == "__main__":
    main()

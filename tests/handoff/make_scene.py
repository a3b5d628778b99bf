"""A tiny Cycles scene for the hand-off tests, made with bpy: python make_scene.py OUT.blend WIDTH HEIGHT.

Asymmetric (a cube off centre, a small sphere top left, the light to one side) so that a window
rendered upside down or shifted would not match the full frame; the cube moves between frames 1
and 2, so a frame rendered as another would not match either. Cycles on the CPU at 4 samples with
a fixed seed, no denoising and no adaptive sampling: every pixel is the same in a border render as
in a full render.
"""
import sys

import bpy


def main(path, width, height):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 4
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.seed = 7
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.frame_start, scene.frame_end = 1, 2

    bpy.ops.object.camera_add(location=(0.0, -6.0, 0.0), rotation=(1.5708, 0.0, 0.0))
    scene.camera = bpy.context.object
    bpy.ops.object.light_add(type="POINT", location=(3.0, -3.0, 3.0))
    bpy.context.object.data.energy = 800.0
    bpy.ops.mesh.primitive_cube_add(size=1.2, location=(0.8, 0.0, -0.4))
    cube = bpy.context.object
    cube.keyframe_insert("location", frame=1)
    cube.location = (-0.4, 0.0, -0.6)
    cube.keyframe_insert("location", frame=2)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(-1.4, 0.0, 0.9))
    world = bpy.data.worlds.new("world")
    world.color = (0.05, 0.08, 0.12)
    scene.world = world
    bpy.ops.wm.save_as_mainfile(filepath=path)


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), int(sys.argv[3]))

#!/usr/bin/python3
"""Writes two_cubes.obj + two_cubes.mtl with VTK's vtkOBJExporter (python3-vtk9): two 10 m
cubes (groups grp1 and grp25) coloured by their actors, so that the OBJ reader's material
colours are tested on files another program wrote. Run from this folder."""
import vtk

ren = vtk.vtkRenderer()
win = vtk.vtkRenderWindow()
win.SetOffScreenRendering(1)
win.AddRenderer(ren)
for centre, colour in [((0, 0, 0), (0.8, 0.2, 0.1)), ((20, 0, 0), (0.1, 0.3, 0.9))]:
    src = vtk.vtkCubeSource()
    src.SetCenter(*centre)
    src.SetXLength(10)
    src.SetYLength(10)
    src.SetZLength(10)
    tri = vtk.vtkTriangleFilter()
    tri.SetInputConnection(src.GetOutputPort())
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(tri.GetOutputPort())
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*colour)
    ren.AddActor(actor)
exporter = vtk.vtkOBJExporter()
exporter.SetRenderWindow(win)
exporter.SetFilePrefix('two_cubes')
exporter.Write()

import vtkmodules.all as vtk
from whitted import vtkWhittedMaterialKeys, vtkWhittedPass

sphere, plane = vtk.vtkSphereSource(), vtk.vtkPlaneSource()
sphere.SetCenter(0, 0, 0.6); sphere.SetThetaResolution(64); sphere.SetPhiResolution(32)
plane.SetOrigin(-2, -2, 0); plane.SetPoint1(2, -2, 0); plane.SetPoint2(-2, 2, 0); plane.SetResolution(8, 8)
ren, win = vtk.vtkRenderer(), vtk.vtkRenderWindow()
win.AddRenderer(ren); win.SetOffScreenRendering(1); win.SetSize(400, 300)
for source in (sphere, plane):
    mapper, actor = vtk.vtkPolyDataMapper(), vtk.vtkActor()
    mapper.SetInputConnection(source.GetOutputPort()); actor.SetMapper(mapper); ren.AddActor(actor)
glass = ren.GetActors().GetItemAsObject(0).GetProperty().GetInformation()
glass.Set(vtkWhittedMaterialKeys.TRANSMITTANCE(), [0.9, 0.9, 0.8], 3)  # kt: refracted share, filters shadows
glass.Set(vtkWhittedMaterialKeys.REFLECTANCE(), [0.1], 1)               # kr: mirrored share
glass.Set(vtkWhittedMaterialKeys.INDEX_OF_REFRACTION(), 1.5)
ren.SetPass(vtkWhittedPass())                                           # the one line that turns ray tracing on
ren.GetActiveCamera().Elevation(-60); ren.ResetCamera(); win.Render()
print(ren.GetPass().GetLastFrameReport())

# The scene conversion of the VTK module: vtkRenderer -> whitted::Scene, one file pair per VTK concept (see
# plugin/README.md, "Data flow"). Listed once, for the module (module/CMakeLists.txt) and for the conversion fuzz
# target (testing/fuzz), which compiles these without the pass and the compositor (they need OpenGL).
set(whitted_conversion_sources
  vtkWhittedSceneConverter.cxx       # the prop walk: what is traced, instances, retiring what is unused
  vtkWhittedGeometryCache.cxx        # converted geometry per (mapper, input or block, options)
  vtkWhittedGeometryTimeCache.cxx    # its time cache: earlier contents kept by fingerprint, and what is kept
  vtkWhittedGeometryFingerprint.cxx  # the fingerprints: a polydata's contents, a mapper's colouring state
  vtkWhittedPolyDataConverter.cxx    # one polydata -> triangles, spheres, tubes
  vtkWhittedGlyphConverter.cxx       # vtkGlyph3DMapper -> one instance per glyph
  vtkWhittedTextureCache.cxx         # vtkTexture -> scene textures
  vtkWhittedMaterialKeys.cxx         # the Whitted information keys (public header: module/CMakeLists.txt)
  vtkWhittedMaterials.cxx            # vtkProperty + Whitted keys -> material
  vtkWhittedLights.cxx               # vtkLight -> lights
  vtkWhittedEnvironment.cxx          # background, skybox, environment texture
  vtkWhittedWarnings.cxx)            # every warning, once per prop
set(whitted_conversion_headers
  vtkWhittedSceneConverter.h
  vtkWhittedGeometryCache.h
  vtkWhittedGeometryTimeCache.h
  vtkWhittedGeometryFingerprint.h
  vtkWhittedPolyDataConverter.h
  vtkWhittedGlyphConverter.h
  vtkWhittedTextureCache.h
  vtkWhittedMaterials.h
  vtkWhittedLights.h
  vtkWhittedEnvironment.h
  vtkWhittedWarnings.h
  vtkWhittedMatrix.h)

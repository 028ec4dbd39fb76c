// Whitted's classic scene as whitted::buildClassicScene builds it (core/scenes.cpp), for POV-Ray 3.7.
// Used by testing/benchmark/run_benchmark.py as the whole-frame anchor:
//   povray +Iclassic.pov +Oout.png +W1024 +H768 -A +WT2 -D +FN File_Gamma=1.0 Declare=TraceLevel=6 \
//          Declare=Bailout=0.00392156862745098
// Our scene is right-handed with the camera looking down -z; POV-Ray is left-handed, so every z is negated here.
// Materials follow VTK's lighting model term by term: ambient = Ka * colour (global ambient_light 1), diffuse =
// Kd * colour * N.L, phong = Ks * (R.V)^power (white), reflection = kr, transmit = kt (unfiltered), ior.
// Output is linear (assumed_gamma 1, File_Gamma 1), like our framebuffer.
#version 3.7;

#ifndef (TraceLevel) #declare TraceLevel = 6; #end        // POV counts the camera ray as level 1: ours + 1
#ifndef (Bailout) #declare Bailout = 1/255; #end           // our contribution threshold
#ifndef (Aspect) #declare Aspect = 4/3; #end               // width / height

global_settings {
  assumed_gamma 1.0
  max_trace_level TraceLevel
  adc_bailout Bailout
  ambient_light rgb 1
}

// vtkCamera: eye (0, 1.8, 4), focal point (0, 0.9, -2.5), view-up +y, vertical view angle 40 degrees.
// POV's angle is horizontal: 2 atan(aspect tan(20 deg)).
camera {
  perspective
  location <0, 1.8, -4>
  look_at <0, 0.9, 2.5>
  sky y
  up y
  right x * Aspect
  angle 2 * degrees(atan(Aspect * tan(radians(20))))
}

background { rgb <0.3, 0.5, 0.85> }

// Point light at (4, 7, 3), white, no attenuation (VTK's default constant attenuation 1)
light_source { <4, 7, -3> color rgb 1 }

// Checkerboard floor: 10 x 14 unit squares, x in [-5, 5], our z in [-11, 3] (POV z in [-3, 11]).
// Square (i, j) is red when i + j is even; POV's checker gives colour 1 where floor(x) + floor(z) is even,
// and floor(x) = i - 5, floor(z) = j - 3 here, so the parities agree. The pattern is shifted by half a unit
// in y so that floor(y) is 0 on the plane and round-off cannot flip the parity.
polygon {
  5, <-5, 0, -3>, <5, 0, -3>, <5, 0, 11>, <-5, 0, 11>, <-5, 0, -3>
  texture {
    pigment { checker color rgb <0.85, 0.1, 0.1> color rgb <0.95, 0.85, 0.1> translate <0, -0.5, 0> }
    finish { ambient 0.15 diffuse 0.85 phong 0 specular 0 reflection 0 }
  }
}

// Mirror sphere: centre (0.9, 1.1, -3.6), radius 1.1
sphere {
  <0.9, 1.1, 3.6>, 1.1
  texture {
    pigment { color rgb 0.7 }
    finish { ambient 0.05 diffuse 0.15 phong 0.6 phong_size 60 specular 0 reflection { 0.8 } }
  }
}

// Glass sphere: centre (-0.7, 0.8, -1.4), radius 0.8; kr 0.1, kt 0.9, ior 1.5, no local colour
sphere {
  <-0.7, 0.8, 1.4>, 0.8
  texture {
    pigment { color rgbt <0.9, 0.9, 0.9, 0.9> }
    finish { ambient 0 diffuse 0 phong 0.8 phong_size 100 specular 0 reflection { 0.1 } }
  }
  interior { ior 1.5 }
}

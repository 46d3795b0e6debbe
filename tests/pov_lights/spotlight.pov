// A spotlight with radius, falloff and tightness over a floor, and a ball
// casting a shadow inside its cone (tests/test_povray.py compares it with
// POV-Ray 3.7's own render).
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 9, -9> look_at <0, 0, 0> angle 50 right x*image_width/image_height }
background { color rgb 0 }
light_source {
  <1, 7, -3>, color rgb <1, 0.9, 0.7>
  spotlight
  point_at <0.5, 0, 0.5>
  radius 14
  falloff 26
  tightness 8
}
// Without radius and falloff: POV-Ray's defaults, 30 and 45 degrees.
light_source { <-6, 5, 4>, color rgb <0.2, 0.3, 0.6> spotlight point_at <-3, 0, 3> }
plane { y, 0 pigment { color rgb 0.8 } finish { ambient 0.05 diffuse 0.9 } }
sphere { <0.3, 1, 0.3>, 0.8 pigment { color rgb <0.9, 0.4, 0.2> } finish { ambient 0.05 phong 0.4 } }

// A cylinder light (parallel rays in a cylinder of radius and falloff) and a
// parallel point light over a floor with a box in the beam
// (tests/test_povray.py compares it with POV-Ray 3.7's own render).
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 10, -8> look_at <0, 0, 0.5> angle 55 right x*image_width/image_height }
background { color rgb 0 }
light_source {
  <-4, 6, -1>, color rgb <0.9, 1, 0.8>
  cylinder
  point_at <0, 0, 1>
  radius 1.5
  falloff 2.5
  tightness 1
}
// Parallel: the shadow of the box falls along the light's axis everywhere.
light_source { <8, 10, 6>, color rgb 0.25 parallel point_at <0, 0, 0> }
plane { y, 0 pigment { color rgb 0.8 } finish { ambient 0.05 diffuse 0.9 } }
box { <-1.5, 0, 0>, <-1, 1.5, 2> pigment { color rgb <0.3, 0.5, 0.9> } finish { ambient 0.05 } }

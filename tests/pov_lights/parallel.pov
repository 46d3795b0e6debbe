// Parallel lights whose plane cuts the scene: a parallel spotlight lights
// all in front of its plane whatever its cone (POV-Ray 3.7 measures the
// cone along the parallel ray itself) and nothing behind; a parallel point
// light lights behind its plane too, where nothing casts a shadow
// (tests/test_povray.py compares it with POV-Ray 3.7's own render).
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0, 12, -10> look_at <0, 0, 0> angle 60 right x*image_width/image_height }
background { color rgb 0 }
light_source { <0, 3, -1>, color rgb <0.8, 0.6, 0.3> spotlight parallel point_at <1, 0, 2> radius 5 falloff 8 }
light_source { <-3, 2, 0>, color rgb <0.2, 0.3, 0.5> parallel point_at <0, 0, 0.5> }
plane { y, 0 pigment { color rgb 0.8 } finish { ambient 0.05 diffuse 0.9 } }
sphere { <1, 1, 1.5>, 0.9 pigment { color rgb <0.9, 0.9, 0.3> } finish { ambient 0.05 } }
sphere { <-2, 1, -3>, 0.9 pigment { color rgb <0.3, 0.9, 0.3> } finish { ambient 0.05 } }

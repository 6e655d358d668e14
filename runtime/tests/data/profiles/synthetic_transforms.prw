! Synthetic SIMPACK wheel file exercising the processing steps (not a real profile).
  header.begin
    version       =  1                       ! Version flag
    type          =  1                       ! 0=rail profile, 1=wheel profile
  header.end
  spline.begin
    approx.smooth  = +0.0e+00
    file           = 'synthetic.txt'         ! Original data file
    comment        = 'synthetic wheel: shift, rotate, bounds, mirror, inversion, cm'
    type           =  0
    point.dist.min = +1.0e-03   ! 1: drops the point 0.0005 cm after the first
    shift.y        = +1.0e+00   ! 2: y + 1 cm
    shift.z        = -0.5e+00   ! 2: z - 0.5 cm
    rotate         = +1.8e+02   ! 3: 180 degrees (units.ang.f below)
    bound.y.min    = -4.5e+00   ! 4: keeps y in [-4.5, 0.5] after rotation
    bound.y.max    = +0.5e+00
    bound.z.min    = +1.0e+00   ! 4: inactive (min > max)
    bound.z.max    = +0.0e+00
    mirror.y       =  1         ! 5
    mirror.z       =  0         ! 5
    inversion      =  1         ! 6
    units.len.f    = +1.0e+02   ! 7: centimetres
    units.ang.f    = +5.729577951308232e+01   ! degrees
    point.begin
   -1.0    0.5
   -0.9995 0.5
    0.0    1.0
    1.0    2.0
    2.0    4.0
    3.0    7.0
    9.0    1.0
    point.end
  spline.end

C Radiation conductors (RadCAD): G is area times the radiation exchange factor, m^2
HEADER CONDUCTOR DATA, CAMERA
     -10, 2, ENV.1, 0.003
     -11, 2, RAD.1, 0.002
HEADER CONDUCTOR DATA, RAD
     -20, 1, ENV.1, 0.008
     -21, 2, ENV.1, 0.008
     -22, 3, ENV.1, 0.008
     -23, 4, ENV.1, 0.008

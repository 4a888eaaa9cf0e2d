// E-Puck2 sensor models, all of them: proximity, ambient light, ground, time of flight, encoders,
// camera, the LEDs the camera sees, and the noise. One header per sensor (proximity.hpp, ...);
// this one includes them all.
//
// Each model is written once:
//  * the formula a fit needs derivatives of (proximity polynomial, light inverse square, ground
//    gain/offset, camera projection) is a template on the scalar, with no branch on a parameter,
//    so that the fits (lib/calibrate on lib/fit) evaluate the very same code with fit::Jet;
//  * the run-time reading (clamp, noise, quantisation) is plain double and reproduces the E-Puck2
//    ARGoS plug-in's arithmetic (as in the plug-in's source, its sensor models, "plug-in
//    compatible") when given the plug-in's coefficients, and the project's fitted ones otherwise
//    (data/fitted/<kind>.json, loaded by lib/calibrate's sensors.hpp, or compile-time constants).
//
// Header-only, standard library only: an ARGoS plug-in or a simulator can include it. Units are in
// every name; angles in radians unless a name says _deg.
#pragma once

#include "epuck2/models/noise.hpp"
#include "epuck2/models/geometry.hpp"
#include "epuck2/models/proximity.hpp"
#include "epuck2/models/light.hpp"
#include "epuck2/models/ground.hpp"
#include "epuck2/models/tof.hpp"
#include "epuck2/models/encoders.hpp"
#include "epuck2/models/drive.hpp"
#include "epuck2/models/camera.hpp"
#include "epuck2/models/leds.hpp"

#pragma once
/// Everything a C++ client needs: Connection, Session and the typed components.
#include "demlink/client/bond_components.hpp"
#include "demlink/client/component.hpp"
#include "demlink/client/connection.hpp"
#include "demlink/client/deformable_bodies.hpp"
#include "demlink/client/particle_components.hpp"
#include "demlink/client/rigid_body.hpp"
#include "demlink/client/scene_components.hpp"
#include "demlink/client/sensor_components.hpp"
#include "demlink/client/session.hpp"
#include "demlink/client/types.hpp"

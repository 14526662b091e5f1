#pragma once

/**
 * @file
 * The contact geometry in one include: the contact nodes and their search
 * (contact_nodes.h: find_contact_nodes()), the zones' surfaces (contact_surfaces.h) and the rigid
 * obstacles (rigid_obstacle.h).
 */

#include <feticontact/contact/contact_nodes.h>
#include <feticontact/contact/contact_surfaces.h>
#include <feticontact/contact/rigid_obstacle.h>

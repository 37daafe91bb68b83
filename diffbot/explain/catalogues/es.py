"""Spanish strings of the worked derivations, in the wording of the ROS 2 class."""

from __future__ import annotations

from typing import Final

STRINGS: Final[dict[str, str]] = {
    "title.ik": "Cinemática inversa: velocidades de las ruedas para v = {v} y ω = {w}",
    "title.fk": "Cinemática directa: velocidad del robot para ω_L = {left} y ω_R = {right}",
    "title.plan": "Plan de movimiento de {duration}, segmentos: {count}",
    "title.odom": "Odometría: un paso de {dt}",
    "section.given": "Datos",
    "section.wheels": "Velocidades de las ruedas",
    "section.body": "Velocidad del robot",
    "section.limit": "Verificación del límite del motor",
    "section.segment": "Segmento {number}: {kind}",
    "section.travel": "Arcos recorridos por las ruedas",
    "section.pose": "Nueva pose",
    "kind.straight": "línea recta de {length}",
    "kind.ccw": "giro antihorario con radio {radius} y ángulo {angle}",
    "kind.cw": "giro horario con radio {radius} y ángulo {angle}",
    "kind.spin": "giro sobre sí mismo de {angle}",
    "label.wheel_radius": "Radio de las ruedas",
    "label.left_wheel_radius": "Radio de las ruedas izquierdas",
    "label.right_wheel_radius": "Radio de las ruedas derechas",
    "label.wheel_separation": "Separación de las ruedas",
    "label.motor_limit": "Límite del motor",
    "label.linear": "Velocidad lineal",
    "label.angular": "Velocidad angular",
    "label.left_speed": "Velocidad angular de la rueda izquierda",
    "label.right_speed": "Velocidad angular de la rueda derecha",
    "label.limit_share": "Fracción del límite del motor que usa la rueda más rápida",
    "label.duration": "Duración",
    "label.path_length": "Longitud del recorrido",
    "label.heading_change": "Cambio de orientación",
    "label.radius": (
        "Radio del giro, con signo como v/ω (negativo en sentido horario hacia adelante o "
        "antihorario hacia atrás)"
    ),
    "label.arc_speed": "Velocidad lineal a partir del giro, como comprobación",
    "label.start_x": "x al inicio",
    "label.start_y": "y al inicio",
    "label.start_heading": "Orientación al inicio",
    "label.end_x": "x al final",
    "label.end_y": "y al final",
    "label.end_heading": "Orientación al final",
    "label.left_before": "Ángulo de la rueda izquierda antes del paso",
    "label.left_after": "Ángulo de la rueda izquierda después del paso",
    "label.right_before": "Ángulo de la rueda derecha antes del paso",
    "label.right_after": "Ángulo de la rueda derecha después del paso",
    "label.joint": "{what}, tal como la ve su articulación (el eje está invertido)",
    "label.time_step": "Paso de tiempo",
    "label.left_arc": "Arco recorrido por la rueda izquierda",
    "label.right_arc": "Arco recorrido por la rueda derecha",
    "label.distance": "Distancia recorrida por el centro",
    "label.chord": (
        "Cuerda del arco (forma sinc: exacta mientras las velocidades de las ruedas son constantes)"
    ),
    "check.within": "{peak} ≤ {limit}: dentro del límite del motor",
    "check.over": "{peak} > {limit}: supera el límite del motor",
    "check.over_plan": (
        "{peak} > {limit}: supera el límite del motor; el segmento necesita al menos {duration}"
    ),
}

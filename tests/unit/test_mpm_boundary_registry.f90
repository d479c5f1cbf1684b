!> Boundary registry: every name belongs to one condition, the choice codes point at the
!> condition of each name, a condition with keys needs the object form; the nodal action of
!> each condition (held components, contact, prescribed velocity, wall); and the velocity face
!> read from a case: its vector, its --check words and every refusal of a bad value; the
!> absorbing face read from a case and its dashpots on one node (the implicit update and its
!> work against the closed form).
program test_mpm_boundary_registry
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: any_same
    use mpm_boundary, only: face_nodes_type, boundary_holder_type, boundary_key_width
    use mpm_boundary_registry, only: boundary_models, boundary_choices, boundary_choice_codes, &
        all_boundary_keys, boundary_allowed, names_of, keys_of
    use mpm_case, only: case_type, read_case_string, case_summary
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_boundary_registry")
    call check_names_and_keys()
    call check_nodes()
    call check_velocity_face()
    call check_absorbing_face()
    call finish(suite)

contains

    !> Names unique over the registry, codes consistent, keys listed once.
    subroutine check_names_and_keys()
        type(boundary_holder_type), allocatable :: models(:)
        character(len=boundary_key_width), allocatable :: choices(:), keys(:), names(:)
        integer, allocatable :: codes(:)
        integer :: i, m, k
        logical :: unique

        models = boundary_models()
        choices = boundary_choices()
        codes = boundary_choice_codes()
        call check(suite, size(codes) == size(choices), "one code per name")
        unique = .true.
        do i = 2, size(choices)
            if (any_same(choices(1:i - 1), trim(choices(i)))) unique = .false.
        end do
        call check(suite, unique, "each name belongs to one condition")
        do i = 1, size(choices)
            names = names_of(models(codes(i))%b)
            call check(suite, any_same(names, trim(choices(i))), &
                trim(choices(i))//": its code points at its condition")
        end do
        keys = all_boundary_keys()
        unique = size(keys) == 10
        if (unique) unique = all(keys == [character(len=boundary_key_width) :: "type", "mu", &
            "velocity", "vp", "vs", "kn", "kt", "file", "record", "scale"])
        call check(suite, unique, "face keys: type, then mu (frictional), velocity, vp, vs, " &
            //"kn, kt (absorbing), file, record, scale (seismic)")
        do m = 1, size(models)
            keys = keys_of(models(m)%b)
            call check(suite, (size(keys) > 0) .eqv. (len(models(m)%b%example()) > 0), &
                models(m)%b%name()//": an example object exactly when it has keys")
            do k = 1, size(keys)
                call check(suite, index(models(m)%b%example(), '"'//trim(keys(k))//'"') > 0, &
                    models(m)%b%name()//": its example gives "//trim(keys(k)))
            end do
        end do
        call check(suite, boundary_allowed() == 'one of "free", "sliding", "fixed", ' &
            //'"periodic", or an ' &
            //'object {"type": "frictional", "mu": 0.4} for a face with Coulomb friction, or ' &
            //'an object {"type": "velocity", "velocity": [0, -0.01]} for a face moving at a ' &
            //'prescribed velocity, or an object {"type": "absorbing", "vp": 300, "vs": 160} ' &
            //'(with "kn", "kt": a Kelvin-Voigt face) ' &
            //"for a face through which waves leave the domain, or an object {" &
            //'"type": "seismic", "file": "record.csv", "record": "acceleration", "scale": ' &
            //'[9.81, 0]} (with "vp", "vs": a compliant base) for a face shaken by an ' &
            //"earthquake record", "the allowed text of messages")
    end subroutine check_names_and_keys

    !> What each condition does to the nodes of a y face in 2D.
    subroutine check_nodes()
        type(boundary_holder_type), allocatable :: models(:)
        type(face_nodes_type) :: nodes
        integer :: m

        models = boundary_models()
        do m = 1, size(models)
            nodes = models(m)%b%nodes(2, 2)
            select case (models(m)%b%name())
            case ("free")
                call check(suite, .not. any(nodes%held) .and. .not. nodes%contact &
                    .and. .not. nodes%keeps_particles, "free: nothing")
            case ("sliding")
                call check(suite, all(nodes%held .eqv. [.false., .true., .false.]) &
                    .and. nodes%keeps_particles, "sliding: the normal component, a wall")
            case ("fixed")
                call check(suite, all(nodes%held .eqv. [.true., .true., .false.]) &
                    .and. all(nodes%velocity == 0.0_wp) .and. .not. nodes%prescribed, &
                    "fixed: both components at zero, no reaction booked")
            case ("frictional")
                call check(suite, nodes%contact .and. .not. any(nodes%held), &
                    "frictional: contact pairs, nothing held")
            case ("velocity")
                call check(suite, all(nodes%held .eqv. [.true., .true., .false.]) &
                    .and. nodes%prescribed .and. nodes%keeps_particles, &
                    "velocity: both components prescribed, a wall")
            case ("absorbing")
                call check(suite, nodes%acts .and. .not. any(nodes%held) .and. &
                    .not. nodes%contact .and. .not. nodes%prescribed .and. &
                    nodes%keeps_particles, "absorbing: acts on its nodes, nothing held, a wall")
            case ("seismic")
                ! (as the registry gives it: no vp, vs, a rigid base at rest)
                call check(suite, all(nodes%held .eqv. [.true., .true., .false.]) &
                    .and. nodes%prescribed .and. nodes%varies .and. nodes%keeps_particles &
                    .and. all(nodes%velocity == 0.0_wp), &
                    "seismic: a rigid base, every component prescribed and changing in time")
            case ("periodic")
                call check(suite, nodes%periodic .and. .not. any(nodes%held) .and. &
                    .not. nodes%contact .and. .not. nodes%prescribed .and. .not. nodes%acts &
                    .and. .not. nodes%keeps_particles, "periodic: tied, nothing held, not a " &
                    //"wall (particles pass to the other face)")
            case default
                call check(suite, .false., models(m)%b%name()//": no nodal check here")
            end select
        end do
    end subroutine check_nodes

    !> The velocity face of a case: its vector, summary and bad values.
    subroutine check_velocity_face()
        type(case_type) :: case
        type(error_type), allocatable :: error
        type(face_nodes_type) :: nodes

        call read_case_string(face_case('{"type": "Velocity", "velocity": [0.5, -0.01]}'), &
            case, error, "velocity_face")
        call check(suite, .not. allocated(error), "velocity face: valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        nodes = case%domain%nodes(2, 2, 2)
        call check(suite, all(nodes%velocity(1:2) == [0.5_wp, -0.01_wp]) .and. nodes%prescribed, &
            "velocity face: its vector")
        call check(suite, index(case_summary(case), "ymax velocity (velocity = (0.5, -0.01) m/s)") &
            > 0, "velocity face: summary")
        call expect_error(face_case('"velocity"'), &
            'domain.boundaries.ymax = "velocity" needs a velocity: write the face as an object, ' &
            //'{"type": "velocity", "velocity": [0, -0.01]}', "velocity as a string")
        call expect_error(face_case('{"type": "velocity"}'), &
            "missing required key 'domain.boundaries.ymax.velocity'", "velocity missing")
        call expect_error(face_case('{"type": "velocity", "velocity": [0, -0.01, 0]}'), &
            "domain.boundaries.ymax.velocity must have 2 numbers", "velocity of 3 in 2D")
        call expect_error(face_case('{"type": "velocity", "velocity": [0, "down"]}'), &
            "domain.boundaries.ymax.velocity[2] has the wrong type: expected a number", &
            "velocity not a number")
        call expect_error(face_case('{"type": "velocity", "velocity": [0, 1e999]}'), &
            "domain.boundaries.ymax.velocity[2] is not a finite number", "velocity not finite")
        call expect_error(face_case('{"type": "velocity", "velocity": 0.1}'), &
            "domain.boundaries.ymax.velocity has the wrong type", "velocity a number")
        call expect_error(face_case('{"type": "fixed", "velocity": [0, 0]}'), &
            "domain.boundaries.ymax.velocity applies to velocity faces only (here " &
            //'domain.boundaries.ymax.type = "fixed"); remove velocity or set "type": ' &
            //'"velocity"', "velocity on a fixed face")
        call expect_error(face_case('{"type": "velocity", "velocity": [0, 0], "mu": 0.1}'), &
            "domain.boundaries.ymax.mu applies to frictional faces only", "mu on a velocity face")
    end subroutine check_velocity_face

    !> The absorbing face of a case: its speeds, summary, bad values, and its dashpots on one
    !> node of a y face: v = v* / (1 + 2 c dt / dx) with c = vp normal, vs along the face, and
    !> the work m (v - v*) . (v0 + v) / 2, v0 = v* - dt a*.
    subroutine check_absorbing_face()
        type(case_type) :: case
        type(error_type), allocatable :: error
        type(face_nodes_type) :: nodes
        real(wp) :: momentum(2, 1), velocity(2, 1), acceleration(2, 1), taken, given, v(2), v0(2), &
            displacement(2, 1), k(2), c(2)
        real(wp), parameter :: dt = 1.0e-3_wp, dx = 0.5_wp, mass = 3.0_wp

        call read_case_string(face_case('{"type": "Absorbing", "vp": 300, "vs": 160}'), &
            case, error, "absorbing_face")
        call check(suite, .not. allocated(error), "absorbing face: valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        nodes = case%domain%nodes(2, 2, 2)
        call check(suite, nodes%acts .and. .not. any(nodes%held), "absorbing face: acts")
        call check(suite, index(case_summary(case), &
            "ymax absorbing (vp = 300 m/s, vs = 160 m/s)") > 0, "absorbing face: summary")
        velocity(:, 1) = [0.2_wp, -0.4_wp]
        acceleration(:, 1) = [10.0_wp, -20.0_wp]
        momentum = mass*velocity
        displacement = 0.0_wp
        call case%domain%face(2, 2)%b%act(2, 2, 0.0_wp, dt, dx, [mass], [dx], &
            reshape([.false., .false.], [2, 1]), momentum, velocity, acceleration, &
            displacement, taken, given)
        call check(suite, all(displacement == 0.0_wp), "absorbing face: a plain dashpot " &
            //"keeps no displacement")
        v = [0.2_wp/(1 + 2*160*dt/dx), -0.4_wp/(1 + 2*300*dt/dx)]
        v0 = [0.2_wp, -0.4_wp] - dt*[10.0_wp, -20.0_wp]
        call check(suite, all(abs(velocity(:, 1) - v) <= 1.0e-15_wp) .and. &
            all(abs(momentum(:, 1) - mass*v) <= 1.0e-14_wp), &
            "absorbing face: implicit dashpots, vs along and vp normal to the face")
        call check(suite, all(abs(acceleration(:, 1) - ([10.0_wp, -20.0_wp] + (v - &
            [0.2_wp, -0.4_wp])/dt)) <= 1.0e-9_wp), "absorbing face: the acceleration follows")
        call check(suite, abs(taken + 0.5_wp*mass*dot_product(v - [0.2_wp, -0.4_wp], v0 + v)) &
            <= 1.0e-15_wp .and. taken > 0.0_wp, "absorbing face: the energy taken, positive")
        ! a component another face holds (a velocity face's corner) is left as it is
        velocity(:, 1) = [0.2_wp, -0.4_wp]
        acceleration(:, 1) = [0.0_wp, -20.0_wp]
        momentum = mass*velocity
        call case%domain%face(2, 2)%b%act(2, 2, 0.0_wp, dt, dx, [mass], [dx], &
            reshape([.true., .false.], [2, 1]), momentum, velocity, acceleration, &
            displacement, taken, given)
        call check(suite, velocity(1, 1) == 0.2_wp .and. acceleration(1, 1) == 0.0_wp .and. &
            momentum(1, 1) == mass*0.2_wp .and. abs(velocity(2, 1) - v(2)) <= 1.0e-15_wp, &
            "absorbing face: a held component is left alone")
        call expect_error(face_case('"absorbing"'), 'domain.boundaries.ymax = "absorbing" ' &
            //"needs the P- and S-wave speeds vp and vs", "absorbing as a string")
        call expect_error(face_case('{"type": "absorbing", "vs": 100}'), &
            "missing required key 'domain.boundaries.ymax.vp'", "vp missing")
        call expect_error(face_case('{"type": "absorbing", "vp": 0, "vs": 100}'), &
            "domain.boundaries.ymax.vp", "vp zero")
        call expect_error(face_case('{"type": "absorbing", "vp": 300, "vs": 270}'), &
            "domain.boundaries.ymax.vs = 270 m/s is not below sqrt(3)/2 vp", &
            "vs not below sqrt(3)/2 vp")
        call expect_error(face_case('{"type": "fixed", "vp": 300}'), &
            "domain.boundaries.ymax.vp applies to absorbing faces only", "vp on a fixed face")
        call expect_error(face_case('{"type": "absorbing", "vp": 300, "vs": 160, '// &
            '"kn": -5, "kt": 1}'), "domain.boundaries.ymax.kn = -5 is out of range", &
            "kn negative")
        call expect_error(face_case('{"type": "absorbing", "vp": 300, "vs": 160, '// &
            '"kn": 5e6}'), "domain.boundaries.ymax.kn is given without kt", "kn without kt")
        ! Kelvin-Voigt: a node at rest, displaced by u, springs back implicitly,
        ! v = -(k A dt^2 / m) / dt u / (1 + c dt / m + k A dt^2 / m), and u follows v
        call read_case_string(face_case('{"type": "absorbing", "vp": 300, "vs": 160, '// &
            '"kn": 4e6, "kt": 2e6}'), case, error, "kelvin_voigt_face")
        call check(suite, .not. allocated(error), "Kelvin-Voigt face: valid")
        if (allocated(error)) return
        call check(suite, index(case_summary(case), "Kelvin-Voigt springs kn = 4e+06 Pa/m") &
            > 0 .or. index(case_summary(case), "Kelvin-Voigt springs kn = 4000000 Pa/m") > 0, &
            "Kelvin-Voigt face: summary")
        velocity = 0.0_wp
        acceleration = 0.0_wp
        momentum = 0.0_wp
        displacement(:, 1) = [1.0e-3_wp, -2.0e-3_wp]
        c = [2*160*dt/dx, 2*300*dt/dx]
        k = [2.0e6_wp, 4.0e6_wp]*dx*dt**2/mass
        v = -k/dt*displacement(:, 1)/(1 + c + k)
        call case%domain%face(2, 2)%b%act(2, 2, 0.0_wp, dt, dx, [mass], [dx], &
            reshape([.false., .false.], [2, 1]), momentum, velocity, acceleration, &
            displacement, taken, given)
        call check(suite, all(abs(velocity(:, 1) - v) <= 1.0e-15_wp) .and. &
            all(abs(displacement(:, 1) - ([1.0e-3_wp, -2.0e-3_wp] + dt*v)) <= 1.0e-18_wp), &
            "Kelvin-Voigt face: the springs (kt along, kn across the face, of the node's " &
            //"area) pull a displaced node back")
    end subroutine check_absorbing_face

    !> A small valid 2D case with the given ymax face.
    function face_case(face) result(text)
        character(len=*), intent(in) :: face
            !! the face's JSON value
        character(len=:), allocatable :: text
            !! the case

        text = '{"domain": {"nx": 2, "ny": 2, "dx": 0.5, "boundaries": {"ymax": '//face// &
            '}}, "materials": [{"name": "m", "type": "linear_elastic", "E": 1e6, "nu": 0.3, ' // &
            '"rho": 1000}], "bodies": [{"material": "m", "min": [0, 0], "max": [1, 1]}], ' // &
            '"time": {"tend": 0.1}}'
    end function face_case

    !> The case is refused with a message holding `text`.
    subroutine expect_error(case_text, text, label)
        character(len=*), intent(in) :: case_text
            !! the case
        character(len=*), intent(in) :: text
            !! part of the message
        character(len=*), intent(in) :: label
            !! name of the check

        type(case_type) :: case
        type(error_type), allocatable :: error

        call read_case_string(case_text, case, error, "face")
        call check(suite, allocated(error), label//": refused")
        if (.not. allocated(error)) return
        call check(suite, index(error%message, text) > 0, label//": message")
        if (index(error%message, text) == 0) print "(a)", "    got: "//error%message
    end subroutine expect_error

end program test_mpm_boundary_registry

!> The abstract boundary condition of a domain face, everything about it in one extension.
!>
!> A condition is one module with an extension of `boundary_type` (and one line in
!> `mpm_boundary_registry`): its names for `domain.boundaries.<face>`, its keys, how it
!> reads and checks them through the case cursor, its words in the --check summary and what
!> it does to the nodes of its face (`face_nodes_type`: the velocity components it holds and
!> their value, whether its nodes are frictional contact pairs, whether it acts on them each
!> step). The case reads it (mpm_case_domain); the grid takes the face's nodal description and
!> the nodal update applies it; a condition that `acts` applies its own nodal action (`act`)
!> to the face's nodes after each nodal update, on plain arrays of those nodes (and the
!> time, for a law that changes in time). A condition
!> sees no model data, only the axis of its face, the dimension and its nodes' values.
module mpm_boundary
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: boundary_type, boundary_holder_type, face_nodes_type, boundary_key_width

    integer, parameter :: boundary_key_width = 10
        !! longest key or type name of a condition ("frictional")

    !> What a condition does to the nodes of its face, as plain data for the grid: the
    !> defaults are those of a free face (nothing held, no contact, particles may leave).
    type :: face_nodes_type
        logical :: held(3) = .false.
            !! velocity components the face holds at `velocity` (only 1..dim are used)
        real(wp) :: velocity(3) = 0.0_wp
            !! value of the held components [m/s]
        logical :: prescribed = .false.
            !! the face moves its nodes at `velocity`: the impulse that takes (its reaction)
            !! is summed per face, and its work is work of the loads
        logical :: varies = .false.
            !! a prescribed velocity that changes in time (`velocity` is its value at t = 0):
            !! the solver takes the condition's `velocity_at` at the start and the end of each
            !! step, and the held components accelerate between the two
        logical :: contact = .false.
            !! the face's nodes are frictional contact pairs (no penetration, Coulomb friction,
            !! lift-off), applied by the contact kernel
        real(wp) :: mu = 0.0_wp
            !! Coulomb friction coefficient of the contact pairs [-]
        logical :: keeps_particles = .false.
            !! a particle moved past the face is put back on it (a wall)
        logical :: periodic = .false.
            !! the face is tied to the opposite one (both periodic): its nodes are that
            !! face's nodes, and a particle leaving through it comes back through the other
        logical :: springs = .false.
            !! the condition's `act` keeps a displacement per node (springs: a Kelvin-Voigt
            !! face), which the grid holds and checkpoints keep
        logical :: acts = .false.
            !! the condition's `act` changes the velocities of the face's nodes after each
            !! nodal update (a dashpot)
    end type face_nodes_type

    !> A boundary condition of one face with its parameters, and how the case file gives it.
    type, abstract :: boundary_type
    contains
        !> Names accepted for the face; the first is the one the summary writes.
        procedure(list_interface), deferred, nopass :: names
        !> Keys of the face object besides "type" (default none).
        procedure, nopass :: keys => boundary_keys
        !> An example object for messages when the condition needs keys (default "": the
        !> name alone, a string, is enough).
        procedure, nopass :: example => boundary_no_text
        !> What the condition is for, after the example in messages ("a face with ...").
        procedure, nopass :: purpose => boundary_no_text
        !> What the name alone lacks ("a friction coefficient"; with `example`).
        procedure, nopass :: needs => boundary_no_text
        !> Read and check its keys of the face object (default: it has none).
        procedure :: read => boundary_read
        !> Its words in the --check summary after its name (" (mu = 0.4)"; default none).
        procedure :: summary => boundary_summary
        !> What it does to the nodes of a face normal to `axis`.
        procedure(nodes_interface), deferred :: nodes
        !> Its action on the nodes of its face after each nodal update, when `nodes` says it
        !> `acts` (default: none).
        procedure :: act => boundary_act
        !> The prescribed velocity at a time, when `nodes` says it `varies` (default: zero).
        procedure :: velocity_at => boundary_velocity_at
        !> The name the summary writes: the first of names.
        procedure :: name => boundary_name
    end type boundary_type

    !> Holder so that conditions of different types fit in one array.
    type :: boundary_holder_type
        class(boundary_type), allocatable :: b
            !! the condition
    end type boundary_holder_type

    abstract interface
        !> A list of names (type names or keys).
        pure subroutine list_interface(list)
            import :: boundary_key_width
            character(len=boundary_key_width), allocatable, intent(out) :: list(:)
                !! the names
        end subroutine list_interface

        !> What the condition does to the nodes of its face.
        pure function nodes_interface(self, axis, dim) result(nodes)
            import :: boundary_type, face_nodes_type
            class(boundary_type), intent(in) :: self
                !! the condition
            integer, intent(in) :: axis
                !! axis normal to the face
            integer, intent(in) :: dim
                !! space dimensions
            type(face_nodes_type) :: nodes
                !! its action on the face's nodes
        end function nodes_interface
    end interface

contains

    !> Default: no keys besides "type".
    pure subroutine boundary_keys(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        allocate (list(0))
    end subroutine boundary_keys

    !> Default: no text.
    pure function boundary_no_text() result(text)
        character(len=:), allocatable :: text
            !! empty

        text = ""
    end function boundary_no_text

    !> Default: nothing to read.
    subroutine boundary_read(self, face, dim, error)
        class(boundary_type), intent(inout) :: self
            !! the condition, its defaults set
        type(cursor_type), intent(in) :: face
            !! the face object ("domain.boundaries.xmin"), its keys checked
        integer, intent(in) :: dim
            !! space dimensions
        type(error_type), allocatable, intent(out) :: error
            !! first error found
    end subroutine boundary_read

    !> The default action on the nodes: none.
    !>
    !> A condition that acts receives the nodes of its face that hold material, after the
    !> nodal update of the step (forces, gravity, damping, the held components and the
    !> contacts applied): their masses, momenta, velocities, accelerations and which of their
    !> components another face holds (those it must leave as they are), and the time at the
    !> start of the step. It changes them as its law says, keeping momentum = mass velocity,
    !> and returns the energy its impulses took from the nodes in this step (positive: taken),
    !> which the energy balance books with the energy the faces stop (`boundary_work`), and
    !> the work of a motion it imposes from outside (a seismic record's incident wave), which
    !> it books as work of the loads (`load_work`). Its law sees only these values, the face
    !> area of each node, its own parameters and a displacement per node that the grid keeps
    !> for it (a spring's stretch: the Kelvin-Voigt face).
    pure subroutine boundary_act(self, axis, dim, time, dt, dx, mass, area, held, momentum, &
        velocity, acceleration, displacement, taken, given)
        class(boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(in) :: time
            !! time at the start of the step [s]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: dx
            !! grid spacing [m]
        real(wp), intent(in) :: mass(:)
            !! mass of each node of the face (n) [kg]
        real(wp), intent(in) :: area(:)
            !! face area each node stands for (n) [m2; m in 2D]
        logical, intent(in) :: held(:, :)
            !! components held by a condition (fixed, sliding, velocity faces; dim, n): left
            !! as they are
        real(wp), intent(inout) :: momentum(:, :)
            !! momentum (dim, n) [kg m/s]
        real(wp), intent(inout) :: velocity(:, :)
            !! velocity (dim, n) [m/s]
        real(wp), intent(inout) :: acceleration(:, :)
            !! acceleration of the step (dim, n) [m/s2]
        real(wp), intent(inout) :: displacement(:, :)
            !! displacement of each node since the start (dim, n) [m]: the state of a law
            !! with springs, which updates it; the others leave it alone
        real(wp), intent(out) :: taken
            !! energy the condition took from these nodes in this step [J]
        real(wp), intent(out) :: given
            !! work of the motion it imposes from outside on these nodes in this step [J]

        taken = 0.0_wp
        given = 0.0_wp
    end subroutine boundary_act

    !> Default: zero (a condition whose `nodes` says it `varies` gives its own).
    pure function boundary_velocity_at(self, time, dim) result(velocity)
        class(boundary_type), intent(in) :: self
            !! the condition
        real(wp), intent(in) :: time
            !! time [s]
        integer, intent(in) :: dim
            !! space dimensions
        real(wp) :: velocity(3)
            !! velocity of the face's nodes (1..dim) [m/s]

        velocity = 0.0_wp
    end function boundary_velocity_at

    !> Default: nothing after the name.
    pure function boundary_summary(self) result(text)
        class(boundary_type), intent(in) :: self
            !! the condition
        character(len=:), allocatable :: text
            !! the words, each starting with a blank

        text = ""
    end function boundary_summary

    !> The name the summary writes.
    pure function boundary_name(self) result(text)
        class(boundary_type), intent(in) :: self
            !! the condition
        character(len=:), allocatable :: text
            !! first of its names

        character(len=boundary_key_width), allocatable :: list(:)

        call self%names(list)
        text = trim(list(1))
    end function boundary_name

end module mpm_boundary

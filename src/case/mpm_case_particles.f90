!> The `particles` key of a case: particles per cell and their placement.
module mpm_case_particles
    use mpm_kinds, only: i8
    use mpm_error, only: error_type
    use mpm_strings, only: int_text
    use mpm_case_cursor, only: cursor_type
    use mpm_case_domain, only: domain_section_type, axis_names
    implicit none
    private
    public :: particles_section_type, read_particles, particle_keys
    public :: dist_regular, dist_random, distribution_names

    ! Particle distribution inside a cell
    integer, parameter :: dist_regular = 1  !! regular sub-grid of ppc^dim points
    integer, parameter :: dist_random = 2   !! one random point in each sub-cell (seeded)
    character(len=*), parameter :: distribution_names(2) = [character(len=7) :: "regular", "random"]
        !! name of each distribution in the case file

    character(len=*), parameter :: particle_keys(*) = [character(len=12) :: "ppc", &
        "distribution", "seed"]
        !! keys of `particles`

    !> `particles`: how the bodies are filled with particles.
    type :: particles_section_type
        integer :: ppc = 2
            !! particles per cell along each direction (ppc**dim per cell)
        integer :: distribution = dist_regular
            !! particle placement inside a cell
        integer :: seed = 1
            !! seed of the random distribution
    end type particles_section_type

contains

    !> `particles`: particles per cell and their placement.
    subroutine read_particles(root, dim, domain, particles, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(inout) :: particles
            !! the particles section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found, has_seed
        integer :: d

        call root%get_section("particles", particle_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_int("ppc", particles%ppc, error, at_least=1, at_most=10)
        if (allocated(error)) return
        do d = 1, dim
            ! particle sub-cells are numbered with default integers along each axis
            if (int(domain%ncells(d), i8)*particles%ppc > huge(1)) then
                call cur%fail(error, "particles.ppc = "//int_text(particles%ppc)//" with " &
                    //"domain.n"//axis_names(d:d)//" = "//int_text(domain%ncells(d)) &
                    //" makes more than "//int_text(huge(1))//" particle positions along " &
                    //axis_names(d:d)//"; use fewer cells or a smaller ppc")
                return
            end if
        end do
        call cur%get_choice("distribution", distribution_names, [dist_regular, dist_random], &
            particles%distribution, error)
        if (allocated(error)) return
        has_seed = cur%has("seed")
        if (has_seed .and. particles%distribution /= dist_random) then
            call cur%fail(error, "particles.seed only applies to particles.distribution" &
                //' = "random"; remove it or set "distribution": "random"')
            return
        end if
        call cur%get_int("seed", particles%seed, error, at_least=0)
    end subroutine read_particles

end module mpm_case_particles
